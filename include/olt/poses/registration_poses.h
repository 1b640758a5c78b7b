#pragma once
// Poses from the depth itself (paper Sec. III-C i): each observation's point cloud is registered
// (GICP or point-to-plane ICP, with a colour term) against a target:
//  - memory `keyframes` (default): the previous observation of the same sensor, the chain of
//    registrations kept relative to the last keyframe. A frame that moved too far from it becomes a
//    keyframe; each new keyframe is also registered against the earlier keyframes of any sensor that
//    see the same place (loop closures), and a pose graph over the keyframes (olt/poses/pose_graph.h)
//    keeps them consistent. Every frame's pose is its keyframe's composed with its chain: a camera
//    that returns to a place is tied to what it saw there, so the error stops growing with time.
//  - `previous`: the previous observation of the same sensor (frame to frame);
//  - `local_map`: the last registered observations of all sensors (the paper's "memory").
// The robot pose is tracked; each sensor's pose is T_world_robot * T_robot_sensor, and the first
// observation fixes the world frame (the robot at the first timestamp is at `T_world_robot_first`).
// Colour images may be taken apart from their depth (Observation::color_dt_s): the colour camera is
// placed at its own time by the motion the velocity estimate gives over that interval.
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "olt/model/recording.h"
#include "olt/model/trajectory.h"
#include "olt/poses/pose_graph.h"
#include "olt/registration/photometric.h"
#include "olt/registration/registration.h"

namespace olt {

/// What each observation is registered against: keyframes with loop closures, the previous observation
/// of the same sensor, or the last N observations of all sensors.
enum class RegistrationMemory { keyframes, previous, local_map };
/// Where each registration starts: the velocity model, the previous pose, or a given trajectory.
enum class InitialGuess { constant_velocity, previous_pose, trajectory };

struct RegistrationPosesConfig {
  RegistrationSetting solver;     ///< the ICP / GICP solver
  double voxel_size_m = 0.03;     ///< downsampling voxel for registration, metres
  int pixel_stride = 2;           ///< back-project every n-th pixel in each direction
  double min_depth_m = 0.3;       ///< registration ignores nearer depth, metres
  double max_depth_m = 4.0;       ///< registration ignores farther depth, metres
  int covariance_neighbors = 10;  ///< k of the k-NN covariance / normal estimate
  /// Colour term: each squared intensity residual (intensities in [0, 1]) counts this many times
  /// against one geometric correspondence's Mahalanobis distance; 0: depth only.
  double photometric_weight = 10;
  int photometric_halvings = 1;            ///< colour term on images halved this many times (0 to 2)
  double photometric_min_gradient = 0.01;  ///< colour term: least intensity gradient per reduced pixel
  double photometric_huber = 0.2;          ///< colour term: residuals beyond this are down-weighted
  bool smoothing = false;                  ///< bilateral filter on depth before registration (not for labels)
  double sigma_s_px = 3;                   ///< smoothing: spatial sigma, pixels (kernel 2*ceil(1.5 sigma)+1)
  double sigma_r_m = 0.05;                 ///< smoothing: range sigma, metres
  RegistrationMemory memory = RegistrationMemory::keyframes;  ///< what each observation is registered against
  int memory_size = 5;                                        ///< local_map: observations kept
  double key_distance_m = 0;        ///< key poses: register only after moving this far (0 = every observation)
  double key_angle_deg = 0;         ///< key poses: ... or turning this much, degrees
  double key_max_interval_s = 0.5;  ///< key poses: register at least this often, seconds
  InitialGuess initial_guess = InitialGuess::constant_velocity;  ///< where each registration starts
  Trajectory guess_trajectory;    ///< initial_guess trajectory: robot poses (odometry, another pose source)
  double max_rmse_m = 0.05;       ///< flag observations whose inlier RMSE is larger, metres
  double min_inlier_ratio = 0.3;  ///< flag observations with fewer inliers than this fraction
  double max_correction_m = 0.1;  ///< with a prior: a larger correction is refused (the prior kept), metres
  double max_correction_deg = 3;  ///< ... or one turning more, degrees
  // memory keyframes
  double keyframe_distance_m = 0.1;     ///< a frame this far from its keyframe becomes a keyframe, metres
  double keyframe_angle_deg = 8;        ///< ... or turned this much from it, degrees
  int loop_candidates = 2;              ///< earlier keyframes a new keyframe is registered against (0 = none)
  double loop_max_distance_m = 0.5;     ///< candidates: camera centres at most this far apart, metres
  double loop_max_angle_deg = 25;       ///< ... and optical axes at most this far apart, degrees
  double loop_min_inlier_ratio = 0.5;   ///< a loop closure needs this fraction of points matched
  double loop_max_correction_m = 0.15;  ///< ... and moves the keyframe at most this far from its estimate, m
  double loop_max_correction_deg = 6;   ///< ... and turns it at most this much, degrees
};

/// The keyframes' points at their final poses, merged on the registration voxel grid: the scene the
/// poses agree on, to score every observation against (olt/poses/consistency.h).
struct KeyframeScene {
  std::vector<Eigen::Vector3d> points;   ///< world frame
  std::vector<Eigen::Vector3d> normals;  ///< unit
};

/// What the keyframe graph did, for the stage summary.
struct KeyframeGraphSummary {
  int keyframes = 0;
  int loop_closures = 0;          ///< loop edges accepted
  int loop_closures_refused = 0;  ///< loop registrations that failed their thresholds
  int optimizations = 0;          ///< pose-graph optimisations run
};

/// What a registration measured, as saved in a pose's quality.
RegistrationQuality registration_quality(const RegistrationResult& r, size_t source_points, size_t target_points,
                                         bool with_color);

/// Feeds observations in time order; call finish() for the poses of all of them, in order.
class RegistrationOdometry {
 public:
  /// The observation's colour image (8-bit BGR, or empty where there is none).
  using ColorLoader = std::function<cv::Mat()>;

  RegistrationOdometry(Calibration calibration, RegistrationPosesConfig config, Pose T_world_robot_first);
  ~RegistrationOdometry();
  /// `load_color` is called only where the colour term will use the image (a registered
  /// observation, photometric_weight > 0); without an image, the observation is registered on depth.
  /// With `prior` (T_world_sensor from another pose source, e.g. the laser), the observation is
  /// registered from it against the targets at their prior poses: a refinement of the prior that
  /// does not drift (key poses do not apply). Where registration fails its thresholds or corrects
  /// the prior by more than max_correction_m / _deg, the prior is kept (quality: refined false).
  void add(const Observation& observation, const cv::Mat& depth, const ColorLoader& load_color,
           const Pose* prior = nullptr);
  std::vector<ObservationPose> finish();

  /// The observation's depth points as registration uses them (depth range, smoothing, stride, voxel
  /// grid), in the sensor frame.
  std::vector<Eigen::Vector3d> sample_points(const Observation& observation, const cv::Mat& depth) const;
  /// After finish(), with memory keyframes: the keyframes' points in the world frame.
  KeyframeScene keyframe_scene() const;
  const KeyframeGraphSummary& graph_summary() const { return summary_; }

 private:
  struct Keyframe;     // keyframe.h
  struct SensorTrack;  // keyframe.h
  /// A registered observation's pose relative to its keyframe (memory keyframes).
  struct Tracked {
    size_t pose_index;  ///< into poses_
    size_t keyframe;
    Pose T_keyframe_sensor;
  };

  struct ColorTarget {
    IntensityImage image;
    Pose T_world_color;  ///< where the image was taken (the observation's pose, or its prior)
  };

  bool uses_color() const { return config_.photometric_weight > 0; }
  /// Whether the observation is registered (a key pose) rather than interpolated.
  bool is_key(double timestamp, const Pose& guess_robot, bool has_prior) const;
  /// The observation's depth in the sensor frame (range, smoothing, stride); a depth image of
  /// another size than the calibration's is an input error naming the file.
  std::vector<Eigen::Vector3d> back_project(const Observation& observation, const cv::Mat& depth) const;
  std::optional<ColorTarget> color_frame(const Observation& observation, const ColorLoader& load_color) const;
  /// Quality thresholds and, with a prior, the largest correction: flags the pose or keeps the prior.
  void judge(const RegistrationResult& r, const Pose& guess, const Pose* prior, Pose* T_world_sensor,
             ObservationPose* pose) const;
  Pose predict_robot(double timestamp) const;
  /// T_sensor(t + color_dt)^-1 ... the sensor's motion from its depth to its colour capture, from the
  /// robot velocity between the last key pose and `T_world_robot` at `timestamp` (identity without one).
  Pose sensor_motion_to_color(const std::string& sensor, double timestamp, const Pose& T_world_robot,
                              double color_dt_s) const;
  void interpolate_pending();
  // memory previous / local_map
  void add_chained(const Observation& o, const cv::Mat& depth, const ColorLoader& load_color, const Pose* prior);
  // memory keyframes (registration_keyframes.cpp)
  void add_tracked(const Observation& o, const cv::Mat& depth, const ColorLoader& load_color);
  /// `cloud` (sensor frame) registered against a registered frame in that frame's own coordinates:
  /// the result is T_frame_sensor.
  /// `color_points_at` gives the source's textured points (or null) once the geometric term has
  /// found T_keyframe_sensor: the colour term then goes on from there.
  RegistrationResult register_to_keyframe(
      const Keyframe& target, const PointSet& cloud, const Pose& guess,
      const std::function<const PhotometricPoints*(const Pose&)>& color_points_at) const;
  /// Links keyframe `keyframe` into the graph: the edge from `chained_from` (the chain of
  /// registrations, T_from_keyframe with its information), or a weak one from the previous keyframe;
  /// then its loop closures.
  void add_keyframe(size_t keyframe, std::optional<size_t> chained_from, const Pose& T_from_keyframe,
                    const Matrix6d& information);
  /// Registers the keyframe against the earlier ones that see the same place; the edges accepted.
  int close_loops(size_t keyframe, std::optional<size_t> tracked_from);
  void optimize_graph(int max_iterations);
  void refresh_robot_keys();

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
  // memory keyframes
  std::vector<std::shared_ptr<Keyframe>> keyframes_;  ///< graph nodes, in creation order
  std::vector<Pose> keyframe_poses_;                  ///< T_world_sensor of each keyframe
  std::vector<PoseGraphEdge> edges_;
  std::vector<Tracked> tracked_;               ///< every registered observation, in order
  std::vector<size_t> robot_key_tracked_;      ///< robot_keys_[k] comes from tracked_[this]
  std::map<std::string, SensorTrack> tracks_;  ///< per sensor
  KeyframeGraphSummary summary_;
  std::vector<double> link_angles_deg_;   ///< every frame-to-frame link's rotation, degrees
  std::vector<double> link_distances_m_;  ///< ... and translation, metres
};

}  // namespace olt
