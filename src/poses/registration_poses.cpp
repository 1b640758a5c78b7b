#include "olt/poses/registration_poses.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "keyframe.h"
#include "olt/core/error.h"
#include "olt/poses/trajectory_poses.h"

namespace olt {
namespace {

// T_a^-1 T_b scaled by f (angle and translation), applied after T_b: constant-velocity prediction.
Pose extrapolate(const Pose& a, const Pose& b, double f) {
  const Pose delta = a.inverse() * b;
  const Eigen::AngleAxisd aa(delta.linear());
  Pose step = Pose::Identity();
  step.linear() = Eigen::AngleAxisd(aa.angle() * f, aa.axis()).toRotationMatrix();
  step.translation() = delta.translation() * f;
  // Re-orthonormalised: the prediction seeds the next registration, and a rotation that is a
  // little off orthonormal would be carried from pose to pose and grow.
  Pose out = b * step;
  out.linear() = Eigen::Quaterniond(out.linear()).normalized().toRotationMatrix();
  return out;
}

// The pose's registration quality, made where there is none yet.
RegistrationQuality& registration_of(ObservationPose* pose) {
  if (!pose->quality.registration) pose->quality.registration.emplace();
  return *pose->quality.registration;
}

// A prior kept: the refinement did not take, and why.
void not_refined(ObservationPose* pose, const char* why) {
  registration_of(pose).refined = false;
  registration_of(pose).not_refined = why;
}

}  // namespace

RegistrationQuality registration_quality(const RegistrationResult& r, size_t source_points, size_t target_points,
                                         bool with_color) {
  RegistrationQuality q;
  RegistrationQuality::Fit fit;
  fit.converged = r.converged;
  fit.iterations = r.iterations;
  fit.inliers = r.inliers;
  fit.inlier_ratio = r.inlier_ratio;
  fit.rmse_m = r.rmse_m;
  fit.source_points = source_points;
  fit.target_points = target_points;
  if (with_color) {
    fit.photometric_points = r.photometric_points;
    fit.photometric_rmse = r.photometric_rmse;
  }
  q.fit = fit;
  return q;
}

RegistrationOdometry::RegistrationOdometry(Calibration calibration, RegistrationPosesConfig config,
                                           Pose T_world_robot_first)
    : calibration_(std::move(calibration)), config_(std::move(config)), T_world_robot_first_(T_world_robot_first) {
  for (const auto& [sensor, cal] : calibration_) rays_[sensor] = pixel_rays(cal.depth);
}

RegistrationOdometry::~RegistrationOdometry() = default;

std::vector<Eigen::Vector3d> RegistrationOdometry::back_project(const Observation& o,
                                                                const cv::Mat& depth_units) const {
  const SensorCalibration& cal = calibration_.at(o.sensor);
  const std::vector<Eigen::Vector2f>& rays = rays_.at(o.sensor);
  if (depth_units.cols != cal.depth.width || depth_units.rows != cal.depth.height)
    throw InputError(o.depth.file(), "depth image is " + std::to_string(depth_units.cols) + "x" +
                                         std::to_string(depth_units.rows) + ", the calibration of sensor '" + o.sensor +
                                         "' says " + std::to_string(cal.depth.width) + "x" +
                                         std::to_string(cal.depth.height));
  cv::Mat depth;
  depth_units.convertTo(depth, CV_32F, 1.0 / cal.depth_scale);
  if (config_.smoothing) {
    cv::Mat smoothed;
    const int diameter = 2 * static_cast<int>(std::ceil(1.5 * config_.sigma_s_px)) + 1;
    cv::bilateralFilter(depth, smoothed, diameter, config_.sigma_r_m, config_.sigma_s_px);
    smoothed.setTo(0, depth == 0);  // the range kernel keeps zeros from leaking in; keep holes holes
    depth = smoothed;
  }
  std::vector<Eigen::Vector3d> points;
  const int stride = config_.pixel_stride;
  points.reserve(static_cast<size_t>(depth.rows / stride + 1) * (depth.cols / stride + 1));
  for (int v = 0; v < depth.rows; v += stride) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; u += stride) {
      const double z = row[u];
      if (z <= 0 || z < config_.min_depth_m || z > config_.max_depth_m) continue;
      const Eigen::Vector2f& r = rays[static_cast<size_t>(v) * depth.cols + u];
      points.emplace_back(r.x() * z, r.y() * z, z);
    }
  }
  return points;
}

std::vector<Eigen::Vector3d> RegistrationOdometry::sample_points(const Observation& o, const cv::Mat& depth) const {
  return voxel_downsample(back_project(o, depth), config_.voxel_size_m);
}

Pose RegistrationOdometry::predict_robot(double t) const {
  const size_t n = robot_keys_.size();
  if (n == 0) return T_world_robot_first_;
  // From another pose source: its motion since the last key pose, applied to that key pose.
  Pose G_key, G_now;
  double gap;
  if (config_.initial_guess == InitialGuess::trajectory &&
      interpolate_trajectory(config_.guess_trajectory, robot_keys_.back().timestamp, &G_key, &gap) &&
      interpolate_trajectory(config_.guess_trajectory, t, &G_now, &gap))
    return robot_keys_.back().pose * (G_key.inverse() * G_now);
  if (n == 1 || config_.initial_guess != InitialGuess::constant_velocity) return robot_keys_.back().pose;
  const auto& a = robot_keys_[n - 2];
  const auto& b = robot_keys_[n - 1];
  const double dt = b.timestamp - a.timestamp;
  if (dt <= 1e-9) return b.pose;  // two sensors at one time: no velocity to measure
  return extrapolate(a.pose, b.pose, (t - b.timestamp) / dt);
}

Pose RegistrationOdometry::sensor_motion_to_color(const std::string& sensor, double t, const Pose& T_world_robot,
                                                  double color_dt_s) const {
  if (color_dt_s == 0) return Pose::Identity();
  // The velocity between the last key pose before t and this one (or between the last two key
  // poses where that one is at t: another sensor at the same time), held over color_dt_s.
  const size_t n = robot_keys_.size();
  const TrajectorySample* a = nullptr;
  Pose b = T_world_robot;
  double tb = t;
  if (n >= 1 && t - robot_keys_[n - 1].timestamp > 1e-6) {
    a = &robot_keys_[n - 1];
  } else if (n >= 2 && robot_keys_[n - 1].timestamp - robot_keys_[n - 2].timestamp > 1e-6) {
    a = &robot_keys_[n - 2];
    b = robot_keys_[n - 1].pose;
    tb = robot_keys_[n - 1].timestamp;
  }
  if (!a) return Pose::Identity();
  const Pose robot_motion = b.inverse() * extrapolate(a->pose, b, color_dt_s / (tb - a->timestamp));
  const Pose& T_robot_sensor = calibration_.at(sensor).T_robot_sensor;
  return T_robot_sensor.inverse() * robot_motion * T_robot_sensor;
}

bool RegistrationOdometry::is_key(double timestamp, const Pose& guess_robot, bool has_prior) const {
  // The motion is predicted with the velocity between the last two key poses, so the first two
  // observations are keys, and a key is taken at least every key_max_interval_s to re-measure it.
  if (has_prior || robot_keys_.size() < 2 || (config_.key_distance_m <= 0 && config_.key_angle_deg <= 0) ||
      timestamp - robot_keys_.back().timestamp >= config_.key_max_interval_s)
    return true;
  const Pose moved = robot_keys_.back().pose.inverse() * guess_robot;
  return moved.translation().norm() >= config_.key_distance_m ||
         rotation_angle(moved) * 180 / M_PI >= config_.key_angle_deg;
}

std::optional<RegistrationOdometry::ColorTarget> RegistrationOdometry::color_frame(
    const Observation& o, const ColorLoader& load_color) const {
  if (!uses_color() || !o.color) return std::nullopt;
  const cv::Mat color = load_color();
  if (color.empty()) return std::nullopt;
  const SensorCalibration& cal = calibration_.at(o.sensor);
  if (color.cols != cal.color.width || color.rows != cal.color.height)
    throw InputError(o.color->file(), "colour image is " + std::to_string(color.cols) + "x" +
                                          std::to_string(color.rows) + ", the calibration of sensor '" + o.sensor +
                                          "' says " + std::to_string(cal.color.width) + "x" +
                                          std::to_string(cal.color.height));
  return ColorTarget{make_intensity_image(color, cal.color, config_.photometric_halvings), Pose::Identity()};
}

void RegistrationOdometry::judge(const RegistrationResult& r, const Pose& guess, const Pose* prior,
                                 Pose* T_world_sensor, ObservationPose* pose) const {
  // In the sensor's own frame: how far registration moved it, wherever the world origin is.
  const Pose correction = guess.inverse() * r.T_target_source;
  char text[200];
  if (r.rmse_m > config_.max_rmse_m || r.inlier_ratio < config_.min_inlier_ratio) {
    std::snprintf(text, sizeof(text), "registration failed thresholds: rmse %.4f m (max %.4f), inliers %.2f (min %.2f)",
                  r.rmse_m, config_.max_rmse_m, r.inlier_ratio, config_.min_inlier_ratio);
    if (prior) {  // a refinement that failed leaves the prior as it was
      *T_world_sensor = *prior;
      not_refined(pose, text);
    } else {
      pose->valid = false;
      pose->flag = text;
    }
  } else if (prior && (correction.translation().norm() > config_.max_correction_m ||
                       rotation_angle(correction) * 180 / M_PI > config_.max_correction_deg)) {
    // Registration disagrees with the prior by more than the prior's own error: more likely a
    // registration sliding along a wall or a floor than a better pose.
    std::snprintf(text, sizeof(text), "correction of %.3f m, %.2f deg beyond max_correction_m / _deg",
                  correction.translation().norm(), rotation_angle(correction) * 180 / M_PI);
    *T_world_sensor = *prior;
    not_refined(pose, text);
  } else if (prior) {
    registration_of(pose).refined = true;
  }
}

void RegistrationOdometry::add(const Observation& o, const cv::Mat& depth, const ColorLoader& load_color,
                               const Pose* prior) {
  // A prior (refinement of another pose source) is registered against the previous observation at
  // its prior pose whatever the memory: the prior already holds the poses together.
  if (config_.memory == RegistrationMemory::keyframes && !prior)
    add_tracked(o, depth, load_color);
  else
    add_chained(o, depth, load_color, prior);
}

void RegistrationOdometry::interpolate_pending() {
  std::vector<size_t> still;
  for (size_t i : pending_) {
    ObservationPose& p = poses_[i];
    Pose T_world_robot;
    double gap;
    if (interpolate_trajectory(robot_keys_, p.timestamp, &T_world_robot, &gap))
      p.T_world_sensor = T_world_robot * calibration_.at(p.sensor).T_robot_sensor;
    else
      still.push_back(i);
  }
  pending_ = still;
}

std::vector<ObservationPose> RegistrationOdometry::finish() {
  if (!keyframes_.empty()) {
    // Memory keyframes: the graph once more to convergence, every registered observation placed on
    // its keyframe, and the observations between them interpolated anew from those poses.
    if (summary_.loop_closures > 0) optimize_graph(20);
    robot_keys_.clear();
    pending_.clear();
    for (const Tracked& t : tracked_) {
      ObservationPose& p = poses_[t.pose_index];
      p.T_world_sensor = keyframe_poses_[t.keyframe] * t.T_keyframe_sensor;
      robot_keys_.push_back({p.timestamp, p.T_world_sensor * calibration_.at(p.sensor).T_robot_sensor.inverse()});
    }
    for (size_t i = 0; i < poses_.size(); ++i)
      if (poses_[i].quality.registration && !poses_[i].quality.registration->key) pending_.push_back(i);
    interpolate_pending();
  }
  // Observations after the last key pose: the constant-velocity prediction (they moved less than
  // the key thresholds from it).
  for (size_t i : pending_)
    poses_[i].T_world_sensor = predict_robot(poses_[i].timestamp) * calibration_.at(poses_[i].sensor).T_robot_sensor;
  pending_.clear();
  return poses_;
}

}  // namespace olt
