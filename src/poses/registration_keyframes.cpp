// Memory `keyframes` of RegistrationOdometry: frame-to-frame chains kept relative to keyframes,
// loop closures between keyframes that see the same place, and a pose graph over them, as keyframe
// RGB-D SLAM does it (Kerl, Sturm, Cremers, "Dense visual SLAM for RGB-D cameras", IROS 2013): a
// camera that returns to a place is tied to what it saw there, so the error stops growing with time.
#include <algorithm>
#include <cmath>

#include "keyframe.h"

namespace olt {

namespace {

// Finite, with an orthonormal rotation: what a registration that diverged may fail to return.
bool is_rigid(const Pose& T) {
  return T.matrix().allFinite() && (T.linear().transpose() * T.linear() - Eigen::Matrix3d::Identity()).norm() < 1e-6;
}

double degrees(const Pose& T) { return rotation_angle(T) * 180 / M_PI; }

// How far apart two camera poses look at the scene: the angle between their optical axes
// (degrees) and the distance between their centres (metres), as one score, each scaled to its limit.
double view_distance(const Pose& a, const Pose& b, double max_distance_m, double max_angle_deg, bool* within) {
  const double d = (a.translation() - b.translation()).norm();
  const double cosine = std::clamp(a.linear().col(2).dot(b.linear().col(2)), -1.0, 1.0);
  const double angle = std::acos(cosine) * 180 / M_PI;
  *within = d <= max_distance_m && angle <= max_angle_deg;
  return d / max_distance_m + angle / max_angle_deg;
}

// The median of `v` (a copy: nth_element reorders it); huge where there is none yet, tiny values
// floored so that a camera that barely moved does not divide by zero.
double median(std::vector<double> v) {
  if (v.empty()) return 1e300;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return std::max(v[v.size() / 2], 1e-9);
}

// Consecutive failed registrations after which a sensor's tracking restarts from its latest frame.
constexpr int kFailuresBeforeRestart = 3;

// The information of an edge that only keeps the graph connected (another sensor's keyframe, a
// frame that failed): weak, so that measured edges decide.
Matrix6d weak_information() { return Matrix6d::Identity(); }

}  // namespace

RegistrationResult RegistrationOdometry::register_to_keyframe(
    const Keyframe& target, const PointSet& cloud, const Pose& guess,
    const std::function<const PhotometricPoints*(const Pose&)>& color_points_at) const {
  // The geometric term first brings the pose within the colour term's few-pixel reach; then both.
  RegistrationResult r = register_point_sets(target.cloud, *target.tree, cloud, guess, config_.solver);
  const PhotometricPoints* color_points = color_points_at(r.T_target_source);
  if (color_points && target.image && !color_points->points.empty()) {
    const PhotometricTerm photometric{color_points, &*target.image, target.T_color_sensor, config_.photometric_weight,
                                      config_.photometric_huber};
    const int geometric_iterations = r.iterations;
    r = register_point_sets(target.cloud, *target.tree, cloud, r.T_target_source, config_.solver, &photometric);
    r.iterations += geometric_iterations;
  }
  return r;
}

void RegistrationOdometry::add_tracked(const Observation& o, const cv::Mat& depth, const ColorLoader& load_color) {
  const SensorCalibration& cal = calibration_.at(o.sensor);
  const Pose& T_robot_sensor = cal.T_robot_sensor;
  ObservationPose pose{o.id, o.sensor, o.timestamp, Pose::Identity(), true, "", {}};
  const Pose guess_robot = predict_robot(o.timestamp);
  if (!is_key(o.timestamp, guess_robot, false)) {
    pose.quality.registration = RegistrationQuality::interpolated();
    pending_.push_back(poses_.size());
    poses_.push_back(pose);
    return;
  }
  const std::vector<Eigen::Vector3d> points = back_project(o, depth);
  auto frame = std::make_shared<Keyframe>();
  frame->sensor = o.sensor;
  frame->timestamp = o.timestamp;
  frame->cloud = downsampled_point_set(points, config_.voxel_size_m, config_.covariance_neighbors);
  frame->tree = std::make_unique<KdTree>(frame->cloud.points);
  std::optional<ColorTarget> color = color_frame(o, load_color);
  // The colour camera at its own time, by the motion the velocity gives between the two captures.
  auto select_color = [&](const Pose& T_world_sensor) {
    if (!color) return;
    const Pose motion =
        sensor_motion_to_color(o.sensor, o.timestamp, T_world_sensor * T_robot_sensor.inverse(), o.color_dt_s);
    frame->T_color_sensor = cal.T_color_depth * motion.inverse();
    frame->color_points =
        select_photometric_points(points, color->image, frame->T_color_sensor, config_.photometric_min_gradient);
  };

  // Frame to frame against the sensor's previous observation, the pose kept relative to the keyframe
  // the chain started from.
  Pose T_world_sensor = guess_robot * T_robot_sensor;
  auto track = tracks_.find(o.sensor);
  bool new_keyframe = true;
  std::optional<size_t> chained_from;
  Pose T_keyframe_sensor = Pose::Identity();
  Matrix6d information = Matrix6d::Zero();
  if (track != tracks_.end()) {
    SensorTrack& t = track->second;
    const Pose T_world_previous = keyframe_poses_[t.keyframe] * t.T_keyframe_frame;
    const Pose guess = T_world_previous.inverse() * T_world_sensor;
    RegistrationResult r = register_to_keyframe(*t.frame, frame->cloud, guess, [&](const Pose& T_previous_sensor) {
      select_color(T_world_previous * T_previous_sensor);
      return color ? &frame->color_points : nullptr;
    });
    pose.quality.registration =
        registration_quality(r, frame->cloud.size(), t.frame->cloud.size(), color && t.frame->image);
    if (!is_rigid(r.T_target_source)) r.T_target_source = guess;
    judge(r, guess, nullptr, &T_world_sensor, &pose);
    T_keyframe_sensor = t.T_keyframe_frame * r.T_target_source;
    T_world_sensor = keyframe_poses_[t.keyframe] * T_keyframe_sensor;
    // The chain's information: the last link's, moved into the keyframe's frame and shared by the
    // links since the keyframe (each about as uncertain as the last).
    const Matrix6d A = adjoint(t.T_keyframe_frame).inverse();
    information = A.transpose() * r.information * A / (t.links + 1);
    if (!pose.valid && ++t.failures < kFailuresBeforeRestart) {
      // A frame that failed is flagged and left out of the chain and the motion model: the next one
      // is registered against the last good frame, from the velocity measured before.
      pose.T_world_sensor = T_world_sensor;
      poses_.push_back(pose);
      return;
    }
    new_keyframe = !pose.valid || T_keyframe_sensor.translation().norm() >= config_.keyframe_distance_m ||
                   degrees(T_keyframe_sensor) >= config_.keyframe_angle_deg;
    if (pose.valid) {
      chained_from = t.keyframe;
      link_angles_deg_.push_back(degrees(r.T_target_source));
      link_distances_m_.push_back(r.T_target_source.translation().norm());
    }
    if (!new_keyframe) t = {frame, t.keyframe, T_keyframe_sensor, t.links + 1, 0};
  } else {
    // The first observation of the recording (the anchor), or a sensor's first: placed by the
    // motion model.
    pose.quality.registration = RegistrationQuality::first_of_sensor();
    if (keyframes_.empty()) T_world_sensor = T_world_robot_first_ * T_robot_sensor;
    select_color(T_world_sensor);
  }
  if (color) frame->image = std::move(color->image);

  size_t keyframe = track != tracks_.end() ? track->second.keyframe : 0;
  if (new_keyframe) {
    keyframe = keyframes_.size();
    keyframe_poses_.push_back(T_world_sensor);
    keyframes_.push_back(frame);
    add_keyframe(keyframe, chained_from, T_keyframe_sensor, information);
    T_keyframe_sensor = Pose::Identity();
    tracks_[o.sensor] = {frame, keyframe, Pose::Identity(), 0, 0};
    pose.quality.registration->new_keyframe = true;
  }
  pose.quality.registration->keyframe = keyframe;
  tracked_.push_back({poses_.size(), keyframe, T_keyframe_sensor});
  pose.T_world_sensor = keyframe_poses_[keyframe] * T_keyframe_sensor;
  poses_.push_back(pose);
  robot_keys_.push_back({o.timestamp, pose.T_world_sensor * T_robot_sensor.inverse()});
  robot_key_tracked_.push_back(tracked_.size() - 1);
  interpolate_pending();
  if (!pose.valid) {
    // Several frames in a row failed: tracking restarts from this one (flagged), a keyframe on a
    // weak edge that loop closures may still tie to the rest; the velocity is unknown.
    robot_keys_.erase(robot_keys_.begin(), robot_keys_.end() - 1);
    robot_key_tracked_.erase(robot_key_tracked_.begin(), robot_key_tracked_.end() - 1);
  }
}

void RegistrationOdometry::add_keyframe(size_t keyframe, std::optional<size_t> chained_from,
                                        const Pose& T_from_keyframe, const Matrix6d& information) {
  ++summary_.keyframes;
  if (keyframe == 0) return;
  // The chain of registrations that led to it is its first edge; a keyframe without one (another
  // sensor's first, a frame that failed) hangs on the previous keyframe by a weak edge.
  if (chained_from) {
    edges_.push_back({*chained_from, keyframe, T_from_keyframe, information, false});
  } else {
    const size_t previous = keyframe - 1;
    edges_.push_back({previous, keyframe, keyframe_poses_[previous].inverse() * keyframe_poses_[keyframe],
                      weak_information(), false});
  }
  if (close_loops(keyframe, chained_from) > 0) optimize_graph(5);
}

int RegistrationOdometry::close_loops(size_t keyframe, std::optional<size_t> tracked_from) {
  if (config_.loop_candidates <= 0) return 0;
  // The earlier keyframes that see the same place, nearest in view first (ties: the older first).
  std::vector<std::pair<double, size_t>> candidates;
  for (size_t k = 0; k < keyframe; ++k) {
    if (tracked_from && k == *tracked_from) continue;
    bool within = false;
    const double score = view_distance(keyframe_poses_[keyframe], keyframe_poses_[k], config_.loop_max_distance_m,
                                       config_.loop_max_angle_deg, &within);
    if (within) candidates.emplace_back(score, k);
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.resize(std::min(candidates.size(), static_cast<size_t>(config_.loop_candidates)));
  const Keyframe& source = *keyframes_[keyframe];
  int accepted = 0;
  for (const auto& [score, k] : candidates) {
    const Pose guess = keyframe_poses_[k].inverse() * keyframe_poses_[keyframe];
    const RegistrationResult r = register_to_keyframe(*keyframes_[k], source.cloud, guess, [&](const Pose&) {
      return source.image ? &source.color_points : nullptr;
    });
    // Accepted only where it overlaps well and agrees with the estimate within what the tracking
    // could have drifted: a registration that slid along a wall is not a loop closure.
    const Pose correction = guess.inverse() * r.T_target_source;
    if (r.inlier_ratio < config_.loop_min_inlier_ratio || r.rmse_m > config_.max_rmse_m ||
        correction.translation().norm() > config_.loop_max_correction_m ||
        degrees(correction) > config_.loop_max_correction_deg) {
      ++summary_.loop_closures_refused;
      continue;
    }
    // Trusted like the chain of frame-to-frame links that would span the same change of view. Its
    // Hessian counts every point as an independent measurement, but what limits a registration is
    // shared by all its points and grows with the change of view (the depth camera's distortion,
    // its rolling shutter, the colour image's blur): taken at face value, the loop closures,
    // which span more than the links, outweigh the chains (TUM fr1_rpy: ATE 0.024 -> 0.020 m).
    const double links = std::max({1.0, degrees(r.T_target_source) / median(link_angles_deg_),
                                   r.T_target_source.translation().norm() / median(link_distances_m_)});
    edges_.push_back({k, keyframe, r.T_target_source, r.information / links, true});
    ++summary_.loop_closures;
    ++accepted;
  }
  return accepted;
}

void RegistrationOdometry::optimize_graph(int max_iterations) {
  PoseGraphSetting setting;
  setting.max_iterations = max_iterations;
  optimize_pose_graph(keyframe_poses_, edges_, 0, setting);
  ++summary_.optimizations;
  refresh_robot_keys();
}

void RegistrationOdometry::refresh_robot_keys() {
  // The tracked poses follow their keyframes; the motion model then predicts from where they are now.
  for (size_t k = 0; k < robot_keys_.size(); ++k) {
    const Tracked& t = tracked_[robot_key_tracked_[k]];
    ObservationPose& p = poses_[t.pose_index];
    p.T_world_sensor = keyframe_poses_[t.keyframe] * t.T_keyframe_sensor;
    robot_keys_[k].pose = p.T_world_sensor * calibration_.at(p.sensor).T_robot_sensor.inverse();
  }
}

KeyframeScene RegistrationOdometry::keyframe_scene() const {
  std::vector<Eigen::Vector3d> points;
  for (size_t k = 0; k < keyframes_.size(); ++k)
    for (const auto& p : keyframes_[k]->cloud.points) points.push_back(keyframe_poses_[k] * p);
  const PointSet merged = downsampled_point_set(points, config_.voxel_size_m, config_.covariance_neighbors);
  return {merged.points, merged.normals};
}

}  // namespace olt
