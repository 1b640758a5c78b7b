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

PointSet merged(const std::deque<PointSet>& sets) {
  PointSet out;
  for (const auto& s : sets) {
    out.points.insert(out.points.end(), s.points.begin(), s.points.end());
    out.covariances.insert(out.covariances.end(), s.covariances.begin(), s.covariances.end());
    out.normals.insert(out.normals.end(), s.normals.begin(), s.normals.end());
  }
  return out;
}

}  // namespace

nlohmann::json registration_quality(const RegistrationResult& r, size_t source_points, size_t target_points,
                                    bool with_color) {
  nlohmann::json q = {{"key", true},
                      {"converged", r.converged},
                      {"iterations", r.iterations},
                      {"inliers", r.inliers},
                      {"inlier_ratio", r.inlier_ratio},
                      {"rmse_m", r.rmse_m},
                      {"source_points", source_points},
                      {"target_points", target_points}};
  if (with_color) {
    q["photometric_points"] = r.photometric_points;
    q["photometric_rmse"] = r.photometric_rmse;
  }
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
    throw InputError(o.depth.path, "depth image is " + std::to_string(depth_units.cols) + "x" +
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
  if (config_.initial_guess == "trajectory" &&
      interpolate_trajectory(config_.guess_trajectory, robot_keys_.back().timestamp, &G_key, &gap) &&
      interpolate_trajectory(config_.guess_trajectory, t, &G_now, &gap))
    return robot_keys_.back().pose * (G_key.inverse() * G_now);
  if (n == 1 || config_.initial_guess != "constant_velocity") return robot_keys_.back().pose;
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
    throw InputError(o.color->path, "colour image is " + std::to_string(color.cols) + "x" + std::to_string(color.rows) +
                                        ", the calibration of sensor '" + o.sensor + "' says " +
                                        std::to_string(cal.color.width) + "x" + std::to_string(cal.color.height));
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
      pose->quality["refined"] = false;
      pose->quality["not_refined"] = text;
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
    pose->quality["refined"] = false;
    pose->quality["not_refined"] = text;
  } else if (prior) {
    pose->quality["refined"] = true;
  }
}

void RegistrationOdometry::add(const Observation& o, const cv::Mat& depth, const ColorLoader& load_color,
                               const Pose* prior) {
  // A prior (refinement of another pose source) is registered against the previous observation at
  // its prior pose whatever the memory: the prior already holds the poses together.
  if (config_.memory == "keyframes" && !prior)
    add_tracked(o, depth, load_color);
  else
    add_chained(o, depth, load_color, prior);
}

void RegistrationOdometry::add_chained(const Observation& o, const cv::Mat& depth, const ColorLoader& load_color,
                                       const Pose* prior) {
  const SensorCalibration& cal = calibration_.at(o.sensor);
  const Pose& T_robot_sensor = cal.T_robot_sensor;
  ObservationPose pose{o.id, o.sensor, o.timestamp, Pose::Identity(), true, "", nullptr};
  const Pose guess_robot = prior ? *prior * T_robot_sensor.inverse() : predict_robot(o.timestamp);

  // Key poses: an observation predicted to be close to the last key pose is not registered; its
  // pose is interpolated between the key poses around it.
  if (!is_key(o.timestamp, guess_robot, prior != nullptr)) {
    pose.quality = {{"key", false}};
    pending_.push_back(poses_.size());
    poses_.push_back(pose);
    return;
  }

  const std::vector<Eigen::Vector3d> points = back_project(o, depth);
  PointSet cloud = downsampled_point_set(points, config_.voxel_size_m, config_.covariance_neighbors);
  // The colour term: this observation's textured pixels against the last colour image of its sensor.
  std::optional<ColorTarget> own_color = color_frame(o, load_color);
  PhotometricPoints color_points;
  PhotometricTerm photometric;
  const auto previous_color = own_color ? previous_color_.find(o.sensor) : previous_color_.end();
  const PointSet* target = nullptr;
  PointSet local_map;
  if (config_.memory == "local_map" && !memory_.empty()) {
    // One map of the last observations: their points merged on the voxel grid, and covariances
    // estimated from the merged neighbourhoods, denser and less noisy than any one observation's.
    local_map = downsampled_point_set(merged(memory_).points, config_.voxel_size_m, config_.covariance_neighbors);
    target = &local_map;
  } else if (auto it = previous_.find(o.sensor); it != previous_.end()) {
    target = &it->second;
  }
  Pose T_world_sensor = guess_robot * T_robot_sensor;
  if (target) {
    const KdTree tree(target->points);
    RegistrationResult r = register_point_sets(*target, tree, cloud, T_world_sensor, config_.registration);
    if (previous_color != previous_color_.end()) {
      // The source's colour camera at its own time, from the motion the geometric pose implies.
      const Pose motion =
          sensor_motion_to_color(o.sensor, o.timestamp, r.T_target_source * T_robot_sensor.inverse(), o.color_dt_s);
      color_points = select_photometric_points(points, own_color->image, cal.T_color_depth * motion.inverse(),
                                               config_.photometric_min_gradient);
      photometric = {&color_points, &previous_color->second.image, previous_color->second.T_world_color.inverse(),
                     config_.photometric_weight, config_.photometric_huber};
    }
    if (photometric.source) {
      // The geometric term first brings the pose within the colour term's few-pixel reach; then both.
      const int geometric_iterations = r.iterations;
      r = register_point_sets(*target, tree, cloud, r.T_target_source, config_.registration, &photometric);
      r.iterations += geometric_iterations;
    }
    pose.quality = registration_quality(r, cloud.size(), target->size(), photometric.source != nullptr);
    const Pose guess = T_world_sensor;
    T_world_sensor = r.T_target_source;
    judge(r, guess, prior, &T_world_sensor, &pose);
  } else {
    pose.quality = {{"key", true}, {"first", true}};
  }
  pose.T_world_sensor = T_world_sensor;
  poses_.push_back(pose);
  robot_keys_.push_back({o.timestamp, T_world_sensor * T_robot_sensor.inverse()});
  interpolate_pending();
  if (!pose.valid) {
    // Tracking restarts from this observation: it becomes the target and the velocity is unknown.
    // Its pose (flagged) is the best estimate there is, so later poses may carry its error.
    robot_keys_.erase(robot_keys_.begin(), robot_keys_.end() - 1);
    memory_.clear();
    previous_.clear();
    previous_color_.clear();
  }
  // With a prior, the observation joins the targets at its prior pose: each refinement is then
  // relative to the prior poses around it, and errors do not chain from one observation to the next.
  const Pose& placed = prior ? *prior : T_world_sensor;
  if (own_color) {
    const Pose motion = sensor_motion_to_color(o.sensor, o.timestamp, placed * T_robot_sensor.inverse(), o.color_dt_s);
    own_color->T_world_color = placed * motion * cal.T_color_depth.inverse();
    previous_color_[o.sensor] = std::move(*own_color);
  }
  PointSet world = transformed(cloud, placed);
  if (config_.memory == "local_map") {
    memory_.push_back(std::move(world));
    while (static_cast<int>(memory_.size()) > config_.memory_size) memory_.pop_front();
  } else {
    previous_[o.sensor] = std::move(world);
  }
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
      if (poses_[i].quality.is_object() && poses_[i].quality.value("key", true) == false) pending_.push_back(i);
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
