#pragma once
// Poses from the depth itself (paper Sec. III-C i): each observation's point cloud is registered
// (GICP or point-to-plane ICP) against the previous observation of the same sensor, or against a
// local map of the last registered observations of all sensors (the paper's "memory"). The robot
// pose is tracked; each sensor's pose is T_world_robot * T_robot_sensor, and the first observation
// fixes the world frame (the robot at the first timestamp is at `T_world_robot_first`).
#include <deque>
#include <functional>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "olt/model/recording.h"
#include "olt/model/trajectory.h"
#include "olt/registration/photometric.h"
#include "olt/registration/registration.h"

namespace olt {

struct RegistrationPosesConfig {
  RegistrationSetting registration;  ///< solver settings
  double voxel_size_m = 0.03;        ///< downsampling voxel for registration, metres
  int pixel_stride = 2;              ///< back-project every n-th pixel in each direction
  double min_depth_m = 0.3;          ///< registration ignores nearer depth, metres
  double max_depth_m = 4.0;          ///< registration ignores farther depth, metres
  int covariance_neighbors = 10;     ///< k of the k-NN covariance / normal estimate
  /// Colour term: each squared intensity residual (intensities in [0, 1]) counts this many times
  /// against one geometric correspondence's Mahalanobis distance; 0: depth only.
  double photometric_weight = 10;
  int photometric_halvings = 1;            ///< colour term on images halved this many times (0 to 2)
  double photometric_min_gradient = 0.01;  ///< colour term: least intensity gradient per reduced pixel
  double photometric_huber = 0.2;          ///< colour term: residuals beyond this are down-weighted
  bool smoothing = false;                  ///< bilateral filter on depth before registration (not for labels)
  double sigma_s_px = 3;                   ///< smoothing: spatial sigma, pixels (kernel 2*ceil(1.5 sigma)+1)
  double sigma_r_m = 0.05;                 ///< smoothing: range sigma, metres
  std::string memory = "previous";         ///< previous (same sensor) | local_map (last N of all sensors)
  int memory_size = 5;                     ///< local_map: observations kept
  double key_distance_m = 0;               ///< key poses: register only after moving this far (0 = every observation)
  double key_angle_deg = 0;                ///< key poses: ... or turning this much, degrees
  double key_max_interval_s = 0.5;         ///< key poses: register at least this often, seconds
  std::string initial_guess = "constant_velocity";  ///< constant_velocity | previous_pose | trajectory
  Trajectory guess_trajectory;    ///< initial_guess trajectory: robot poses (odometry, another pose source)
  double max_rmse_m = 0.05;       ///< flag observations whose inlier RMSE is larger, metres
  double min_inlier_ratio = 0.3;  ///< flag observations with fewer inliers than this fraction
  double max_correction_m = 0.1;  ///< with a prior: a larger correction is refused (the prior kept), metres
  double max_correction_deg = 3;  ///< ... or one turning more, degrees
};

/// Feeds observations in time order; call finish() for the poses of all of them, in order.
class RegistrationOdometry {
 public:
  /// The observation's colour image (8-bit BGR, or empty where there is none).
  using ColorLoader = std::function<cv::Mat()>;

  RegistrationOdometry(Calibration calibration, RegistrationPosesConfig config, Pose T_world_robot_first);
  /// `load_color` is called only where the colour term will use the image (a registered
  /// observation, photometric_weight > 0); without an image, the observation is registered on depth.
  /// With `prior` (T_world_sensor from another pose source, e.g. the laser), the observation is
  /// registered from it against the targets at their prior poses: a refinement of the prior that
  /// does not drift (key poses do not apply). Where registration fails its thresholds or corrects
  /// the prior by more than max_correction_m / _deg, the prior is kept (quality: refined false).
  void add(const Observation& observation, const cv::Mat& depth, const ColorLoader& load_color,
           const Pose* prior = nullptr);
  std::vector<ObservationPose> finish();

 private:
  struct ColorTarget {
    IntensityImage image;
    Pose T_world_color;  ///< where the image was taken (the observation's pose, or its prior)
  };

  bool uses_color() const { return config_.photometric_weight > 0; }
  /// Whether the observation is registered (a key pose) rather than interpolated.
  bool is_key(double timestamp, const Pose& guess_robot, bool has_prior) const;
  std::vector<Eigen::Vector3d> back_project(const cv::Mat& depth, const SensorCalibration& cal,
                                            const std::vector<Eigen::Vector2f>& rays) const;
  std::optional<ColorTarget> color_frame(const Observation& observation, const ColorLoader& load_color) const;
  /// Quality thresholds and, with a prior, the largest correction: flags the pose or keeps the prior.
  void judge(const RegistrationResult& r, const Pose& guess, const Pose* prior, Pose* T_world_sensor,
             ObservationPose* pose) const;
  Pose predict_robot(double timestamp) const;
  void interpolate_pending();

  Calibration calibration_;
  RegistrationPosesConfig config_;
  Pose T_world_robot_first_;
  std::map<std::string, std::vector<Eigen::Vector2f>> rays_;  ///< per sensor
  std::vector<ObservationPose> poses_;                        ///< every observation so far, in order
  Trajectory robot_keys_;                                     ///< robot poses at registered (key) observations
  std::map<std::string, PointSet> previous_;                  ///< last key cloud of each sensor, world frame
  std::map<std::string, ColorTarget> previous_color_;         ///< colour term: last key image of each sensor
  std::deque<PointSet> memory_;  ///< local map: last key clouds of all sensors, world frame
  std::vector<size_t> pending_;  ///< non-key observations waiting for the next key pose
};

}  // namespace olt
