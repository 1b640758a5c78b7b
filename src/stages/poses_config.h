#pragma once
// The `poses` stage's config and its methods' bodies, shared by the files of the stage:
// poses_params.cpp (the params table), poses_registration.cpp, poses_laser.cpp, poses_stage.cpp.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/config/params.h"
#include "olt/poses/consistency.h"
#include "olt/poses/registration_poses.h"
#include "olt/stages/laser.h"
#include "olt/stages/stage.h"

namespace olt {

enum class PosesMethod { trajectory, registration, laser };
enum class TrajectoryFrame { sensor, robot };  ///< whose pose a trajectory gives
enum class AnchorFit { first, all };
enum class LaserRefine { none, registration };

struct PosesConfig {
  PosesMethod method = PosesMethod::trajectory;  ///< an imported trajectory, registration, or the laser
  // method: trajectory
  std::string trajectory;                           ///< TUM trajectory file; default: the recording's ground truth
  TrajectoryFrame frame = TrajectoryFrame::sensor;  ///< the trajectory gives T_world_sensor or T_world_robot
  double max_gap_s = 0.05;                          ///< largest time to the nearest trajectory sample, seconds
  // method: registration
  RegistrationPosesConfig registration;  ///< every setting and its default lives there
  std::string guess_trajectory;          ///< initial_guess trajectory: TUM file of robot poses (e.g. odometry)
  std::string anchor;  ///< TUM trajectory of the first observation's sensor pose (e.g. a ground truth); default: robot
                       ///< at the origin
  bool anchor_to_groundtruth = false;  ///< take that pose from the recording's own ground truth instead
  /// first: the first observation placed by the anchor; all: the registered trajectory moved by the
  /// rigid transform that fits it best to the anchor at every observation of that sensor it covers
  AnchorFit anchor_fit = AnchorFit::first;
  ConsistencySetting consistency;  ///< memory keyframes: every observation scored against the keyframes' scene
  // method: laser
  LaserMapSettings laser;                  ///< localization: scan matching and ranges (laser_* params)
  std::string map;                         ///< map.txt of a laser_map run; default: the laser_map stage upstream
  std::vector<double> initial_pose;        ///< x y (m) yaw (deg): the robot at the first scan, in the map
  double max_scan_gap_s = 1.0;             ///< flag observations between scans farther apart, seconds
  LaserRefine refine = LaserRefine::none;  ///< registration: laser poses as its guess and anchor
};

std::shared_ptr<const Params<PosesConfig>> poses_params();

/// Reads the observation's colour image when the registration asks for it.
RegistrationOdometry::ColorLoader color_of(const Observation& o);

/// method registration: every observation registered (RegistrationOdometry), with memory keyframes
/// scored against the keyframes' scene; the graph's figures go into `summary`.
std::vector<ObservationPose> registered_poses(const PosesConfig& c, const Recording& recording,
                                              const Calibration& calibration, nlohmann::json& summary);

/// anchor_fit all: the registered trajectory moved as one rigid body onto the anchor trajectory.
void fit_to_anchor(const PosesConfig& c, const Recording& recording, const Calibration& calibration,
                   std::vector<ObservationPose>& poses);

/// method laser: the scans localized in the map, the robot pose interpolated at each observation,
/// refined by registration where asked; writes and publishes the robot trajectory.
std::vector<ObservationPose> laser_poses(const StageContext& ctx, ArtifactWriter& out, nlohmann::json& summary,
                                         const PosesConfig& c, const Recording& recording,
                                         const Calibration& calibration);

}  // namespace olt
