// `poses` with method laser: the robot's scans localized in a 2D map, the robot pose at each
// observation, optionally refined by registration.
#include <algorithm>

#include "olt/core/error.h"
#include "olt/core/image.h"
#include "olt/core/progress.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/poses/laser_poses.h"
#include "olt/poses/trajectory_poses.h"
#include "olt/stages/artifacts.h"
#include "poses_config.h"

namespace olt {
namespace {

PointMap2D load_map(const std::string& file) {
  const PointMapText text = parse_point_map(file, read_file(file));
  PointMap2D map(1e-4);  // the file's points are already thinned
  map.add(text.points, text.normals);
  map.build();
  return map;
}

// The scans localized in the map, from the initial pose (the job's, else the map's own first).
std::vector<ScanPose> localized_scans(const PosesInputs& in, const PosesConfig& c) {
  const LaserData laser = load_laser_data(in.recording, in.stage);
  Pose2 start = Pose2::Identity();
  if (!c.initial_pose.empty()) {
    start = pose2(c.initial_pose[0], c.initial_pose[1], c.initial_pose[2] * M_PI / 180);
  } else if (!in.laser_map.empty() && c.map.empty() && !in.laser_map_scans.empty()) {  // the map's own first pose
    start = in.laser_map_scans.front().T_map_robot;
  }
  const PointMap2D map = load_map(c.map.empty() ? in.laser_map.string() : c.map);
  return localize_scans(map, laser.scans, laser.odometry, c.laser, start);
}

// Anchored: the map placed in the ground truth's world so that the robot at the first scan localized
// is where the ground truth puts it (boxes drawn in that world then apply).
void anchor_to_groundtruth(const PosesInputs& in, std::vector<ScanPose>& scans) {
  const auto anchor = std::find_if(scans.begin(), scans.end(), [](const ScanPose& s) { return s.valid; });
  if (anchor == scans.end()) return;
  const Recording& recording = in.recording;
  if (recording.groundtruth.empty() || recording.groundtruth_frame != "robot")
    throw InputError("stage '" + in.stage + "'",
                     "anchor_to_groundtruth with method laser needs the recording's ground truth of the robot");
  const Trajectory truth = parse_tum_trajectory(recording.groundtruth, read_file(recording.groundtruth));
  Pose T_world_robot;
  double gap;
  if (!interpolate_trajectory(truth, anchor->timestamp, &T_world_robot, &gap))
    throw InputError(recording.groundtruth, "does not cover the time of the first scan localized");
  const Pose2 T_world_map = to_pose2(T_world_robot) * anchor->T_map_robot.inverse();
  for (auto& s : scans) s.T_map_robot = T_world_map * s.T_map_robot;
}

// Each observation the laser placed, registered from its laser pose against the last ones at
// theirs (the registration settings; memory: previous or local_map).
void refine_by_registration(const PosesInputs& in, const PosesConfig& c, std::vector<ObservationPose>& poses) {
  RegistrationOdometry refine(in.calibration, c.registration, Pose::Identity());
  std::vector<size_t> refined_index;
  Progress progress("observations refined", poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    progress.advance();
    if (!poses[i].valid) continue;
    const Observation& o = in.recording.observations[i];
    refine.add(o, read_grey16(o.depth.file()), color_of(o), &poses[i].T_world_sensor);
    refined_index.push_back(i);
  }
  const std::vector<ObservationPose> refined = refine.finish();
  for (size_t k = 0; k < refined.size(); ++k) {
    ObservationPose& p = poses[refined_index[k]];
    p.quality.registration = refined[k].quality.registration;
    p.T_world_sensor = refined[k].T_world_sensor;
    p.valid = refined[k].valid;
    p.flag = refined[k].flag;
  }
}

}  // namespace

// Laser poses: the scans localized in the map, the robot pose interpolated at each observation;
// with refine, registration from there (the laser's motion as its guess, its first pose as anchor).
PosesResult laser_poses(const PosesInputs& in, const PosesConfig& c) {
  std::vector<ScanPose> scans = localized_scans(in, c);
  if (c.anchor_to_groundtruth) anchor_to_groundtruth(in, scans);
  PosesResult result;
  nlohmann::json& summary = result.figures;
  summary["scans"] = scans.size();
  summary["scans_failed"] = std::count_if(scans.begin(), scans.end(), [](const ScanPose& s) { return !s.valid; });
  LaserPoses placed = poses_from_scans(in.recording.observations, scans, in.calibration, c.max_scan_gap_s);
  summary["observations_outside_scans"] = placed.outside_scans;
  summary["observations_in_scan_gaps"] = placed.in_scan_gaps;
  summary["observations_next_to_failed_scans"] = placed.next_to_failed_scans;
  result.scans = std::move(scans);
  result.poses = std::move(placed.poses);
  if (c.refine == LaserRefine::registration) refine_by_registration(in, c, result.poses);
  return result;
}

}  // namespace olt
