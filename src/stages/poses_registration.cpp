// `poses` with method registration: the odometry over every observation, the consistency of each
// with the keyframes' scene, and the fit to an anchor trajectory.
#include <atomic>
#include <cstdio>

#include "olt/core/error.h"
#include "olt/core/image.h"
#include "olt/core/parallel.h"
#include "olt/core/progress.h"
#include "olt/formats/tum.h"
#include "olt/poses/trajectory_poses.h"
#include "poses_config.h"

namespace olt {

RegistrationOdometry::ColorLoader color_of(const Observation& o) {
  return [&o] { return o.color ? read_color(o.color->file()) : cv::Mat(); };
}

namespace {

// Memory keyframes: every observation placed by its pose against the keyframes' scene; those that
// disagree with it are flagged (their labels would be off by as much).
int score_consistency(const PosesConfig& c, const Recording& recording, const RegistrationOdometry& odometry,
                      std::vector<ObservationPose>& poses) {
  const KeyframeScene scene = odometry.keyframe_scene();
  const SceneSurface surface(scene.points, scene.normals);
  // Each observation on its own (its depth read again, scored, its pose marked): in parallel, the
  // same result in any order.
  std::atomic<int> inconsistent{0};
  parallel_for(poses.size(), [&](size_t i) {
    ObservationPose& p = poses[i];
    if (!p.valid) return;
    const Observation& o = recording.observations[i];
    const Consistency score =
        surface.score(odometry.sample_points(o, read_grey16(o.depth.file())), p.T_world_sensor, c.consistency);
    p.quality.consistency = ConsistencyQuality{score.fraction, score.coverage, score.rmse_m, score.points};
    if (score.fraction >= c.consistency.min_fraction) return;
    char text[160];
    std::snprintf(text, sizeof(text),
                  "inconsistent with the scene: %.0f%% of its points near it within %.3f m of it (min %.0f%%)",
                  100 * score.fraction, c.consistency.distance_m, 100 * c.consistency.min_fraction);
    p.valid = false;
    p.flag = text;
    ++inconsistent;
  });
  return inconsistent;
}

}  // namespace

std::vector<ObservationPose> registered_poses(const PosesConfig& c, const Recording& recording,
                                              const Calibration& calibration, nlohmann::json& summary) {
  Pose T_world_robot_first = Pose::Identity();
  const std::string anchor_file = c.anchor_to_groundtruth ? recording.groundtruth : c.anchor;
  if (c.anchor_to_groundtruth && anchor_file.empty())
    throw InputError("anchor_to_groundtruth", "the recording has no ground-truth trajectory");
  if (!anchor_file.empty() && !recording.observations.empty()) {
    double gap;
    const Trajectory anchor = parse_tum_trajectory(anchor_file, read_file(anchor_file));
    const Observation& first = recording.observations.front();
    const double t = first.timestamp + calibration.at(first.sensor).time_offset_s;
    if (!interpolate_trajectory(anchor, t, &T_world_robot_first, &gap))
      throw InputError(anchor_file, "does not cover the first observation's time " + std::to_string(first.timestamp));
    const bool robot_frame = c.anchor_to_groundtruth && recording.groundtruth_frame == "robot";
    if (!robot_frame) T_world_robot_first = T_world_robot_first * calibration.at(first.sensor).T_robot_sensor.inverse();
  }
  RegistrationPosesConfig config = c.registration;
  if (!c.guess_trajectory.empty())
    config.guess_trajectory = parse_tum_trajectory(c.guess_trajectory, read_file(c.guess_trajectory));
  RegistrationOdometry odometry(calibration, config, T_world_robot_first);
  Progress progress("observations registered", recording.observations.size());
  for (const auto& o : recording.observations) {
    odometry.add(o, read_grey16(o.depth.file()), color_of(o));
    progress.advance();
  }
  std::vector<ObservationPose> poses = odometry.finish();
  if (config.memory != RegistrationMemory::keyframes) return poses;
  const KeyframeGraphSummary& graph = odometry.graph_summary();
  summary["keyframes"] = graph.keyframes;
  summary["loop_closures"] = graph.loop_closures;
  summary["loop_closures_refused"] = graph.loop_closures_refused;
  summary["inconsistent"] = score_consistency(c, recording, odometry, poses);
  return poses;
}

// anchor_fit all: the registered trajectory (whose shape comes from the images alone) moved as one
// rigid body onto the anchor trajectory, fitted over every valid observation of the first
// observation's sensor that it covers; boxes drawn in the anchor's frame then fit on average
// rather than only as well as one pose.
void fit_to_anchor(const PosesConfig& c, const Recording& recording, const Calibration& calibration,
                   std::vector<ObservationPose>& poses) {
  const std::string file = c.anchor_to_groundtruth ? recording.groundtruth : c.anchor;
  if (file.empty() || poses.empty()) return;
  const Trajectory anchor = parse_tum_trajectory(file, read_file(file));
  const bool robot_frame = c.anchor_to_groundtruth && recording.groundtruth_frame == "robot";
  const std::string& sensor = poses.front().sensor;
  const SensorCalibration& cal = calibration.at(sensor);
  std::vector<Pose> P, Q;
  for (const auto& p : poses) {
    Pose T;
    double gap;
    if (!p.valid || p.sensor != sensor || !interpolate_trajectory(anchor, p.timestamp + cal.time_offset_s, &T, &gap))
      continue;
    P.push_back(p.T_world_sensor);
    Q.push_back(robot_frame ? T * cal.T_robot_sensor : T);
  }
  const Pose T_anchor_registered = pose_alignment(P, Q);
  for (auto& p : poses) p.T_world_sensor = T_anchor_registered * p.T_world_sensor;
}

}  // namespace olt
