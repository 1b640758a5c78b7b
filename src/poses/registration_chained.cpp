// Memories `previous` and `local_map` of RegistrationOdometry: each observation registered against
// the sensor's previous registered observation, or against the last registered observations of all
// sensors merged into one local map (the paper's "memory"); with a prior (laser poses' refine), from
// the prior against the targets at their priors.
#include "keyframe.h"
#include "olt/poses/registration_poses.h"

namespace olt {
namespace {

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

void RegistrationOdometry::add_chained(const Observation& o, const cv::Mat& depth, const ColorLoader& load_color,
                                       const Pose* prior) {
  const SensorCalibration& cal = calibration_.at(o.sensor);
  const Pose& T_robot_sensor = cal.T_robot_sensor;
  ObservationPose pose{o.id, o.sensor, o.timestamp, Pose::Identity(), true, "", {}};
  const Pose guess_robot = prior ? *prior * T_robot_sensor.inverse() : predict_robot(o.timestamp);

  // Key poses: an observation predicted to be close to the last key pose is not registered; its
  // pose is interpolated between the key poses around it.
  if (!is_key(o.timestamp, guess_robot, prior != nullptr)) {
    pose.quality.registration = RegistrationQuality::interpolated();
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
  if (config_.memory == RegistrationMemory::local_map && !memory_.empty()) {
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
    RegistrationResult r = register_point_sets(*target, tree, cloud, T_world_sensor, config_.solver);
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
      r = register_point_sets(*target, tree, cloud, r.T_target_source, config_.solver, &photometric);
      r.iterations += geometric_iterations;
    }
    pose.quality.registration = registration_quality(r, cloud.size(), target->size(), photometric.source != nullptr);
    const Pose guess = T_world_sensor;
    T_world_sensor = r.T_target_source;
    judge(r, guess, prior, &T_world_sensor, &pose);
  } else {
    pose.quality.registration = RegistrationQuality::first_of_sensor();
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
  if (config_.memory == RegistrationMemory::local_map) {
    memory_.push_back(std::move(world));
    while (static_cast<int>(memory_.size()) > config_.memory_size) memory_.pop_front();
  } else {
    previous_[o.sensor] = std::move(world);
  }
}

}  // namespace olt
