#pragma once
// The `poses` stage: the 6-DoF pose of every RGB-D observation. Method `trajectory` imports a
// TUM-format trajectory (the job's file, or the recording's own ground truth) and interpolates it;
// `registration` aligns the observations' depth; `laser` localizes the robot's laser scans in a 2D
// map and interpolates the robot pose at each observation, optionally refined by registration.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/core/fs.h"
#include "olt/laser/laser_map.h"
#include "olt/model/recording.h"
#include "olt/poses/consistency.h"
#include "olt/poses/registration_poses.h"

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
  LaserMapSettings laser;                  ///< localization: scan matching and ranges (the laser: section)
  std::string map;                         ///< map.txt of a laser_map run; default: the laser_map stage upstream
  std::vector<double> initial_pose;        ///< x y (m) yaw (deg): the robot at the first scan, in the map
  double max_scan_gap_s = 1.0;             ///< flag observations between scans farther apart, seconds
  LaserRefine refine = LaserRefine::none;  ///< registration: laser poses as its guess and anchor
};

struct PosesInputs {
  std::string stage;  ///< the stage's id, for messages
  Recording recording;
  Calibration calibration;
  fs::path laser_map;                     ///< map.txt of the laser_map stage upstream; "" when none
  std::vector<ScanPose> laser_map_scans;  ///< that stage's scan poses (its first: the default start)
};

struct PosesResult {
  std::vector<ObservationPose> poses;                 ///< one per observation, in order
  std::vector<ScanPose> scans;                        ///< method laser: every scan's pose, in the poses' frame
  nlohmann::json figures = nlohmann::json::object();  ///< the method's counts (scans, loop closures, ...)
  std::vector<std::string> sensors;                   ///< the recording's: each gets a trajectory file
};

/// Throws InputError naming a file that covers no observation, or a missing trajectory.
PosesResult run_poses(const PosesInputs& in, const PosesConfig& c);

}  // namespace olt
