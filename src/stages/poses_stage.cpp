// `poses`: the 6-DoF pose of every RGB-D observation. Method `trajectory` imports a TUM-format
// trajectory (the job's file, or the recording's own ground truth) and interpolates it;
// `registration` aligns the observations' depth; `laser` localizes the robot's laser scans in a
// 2D map and interpolates the robot pose at each observation, optionally refined by registration.
// This file: the stage's files, its function, codec and checks; the config in olt/stages/poses.h,
// the params table in poses_params.cpp, the methods in poses_registration.cpp and poses_laser.cpp.
#include <algorithm>

#include "olt/core/error.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/poses/trajectory_poses.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
#include "olt/stages/poses.h"
#include "olt/stages/typed_stage.h"
#include "poses_config.h"

namespace olt {
namespace {

std::vector<fs::path> files_read(const StageDecl& stage) {
  const PosesConfig c = poses_params()->from_json(stage.params);
  std::vector<fs::path> files;
  if (!c.map.empty()) {
    parse_point_map(c.map, read_file(c.map));
    files.push_back(c.map);
  }
  for (const std::string& file : {c.trajectory, c.anchor, c.guess_trajectory}) {
    if (file.empty()) continue;
    parse_tum_trajectory(file, read_file(file));  // bad input is found before anything runs
    files.push_back(file);
  }
  return files;
}

PosesResult trajectory_or_registered_poses(const PosesInputs& in, const PosesConfig& c) {
  PosesResult result;
  const Recording& recording = in.recording;
  if (c.method == PosesMethod::registration) {
    result.poses = registered_poses(c, recording, in.calibration, result.figures);
    if (c.anchor_fit == AnchorFit::all) fit_to_anchor(c, recording, in.calibration, result.poses);
    return result;
  }
  const std::string file = c.trajectory.empty() ? recording.groundtruth : c.trajectory;
  if (file.empty()) throw InputError("stage '" + in.stage + "'", "no trajectory given and the recording has none");
  const Trajectory trajectory = parse_tum_trajectory(file, read_file(file));
  const bool robot_frame =
      c.frame == TrajectoryFrame::robot || (c.trajectory.empty() && recording.groundtruth_frame == "robot");
  result.poses = poses_from_trajectory(recording.observations, trajectory, in.calibration, {c.max_gap_s, robot_frame});
  // Some observations outside the trajectory are flagged; none inside it is a wrong file.
  const auto& poses = result.poses;
  if (!poses.empty() && std::none_of(poses.begin(), poses.end(), [](const auto& p) { return p.valid; }))
    throw InputError(file, "covers none of the " + std::to_string(poses.size()) + " observations (trajectory " +
                               (trajectory.empty() ? std::string("empty")
                                                   : std::to_string(trajectory.front().timestamp) + " to " +
                                                         std::to_string(trajectory.back().timestamp) + " s") +
                               ", observations " + std::to_string(recording.observations.front().timestamp) + " to " +
                               std::to_string(recording.observations.back().timestamp) + " s)");
  return result;
}

}  // namespace

PosesResult run_poses(const PosesInputs& in, const PosesConfig& c) {
  PosesResult result = c.method == PosesMethod::laser ? laser_poses(in, c) : trajectory_or_registered_poses(in, c);
  for (const auto& s : in.recording.sensors) result.sensors.push_back(s.id);
  return result;
}

namespace {

PosesInputs load(const StageContext& context) {
  PosesInputs in{
      context.stage.id, load_recording(context.need("source")), load_calibration(context.need("calibrate")), {}, {}};
  if (const StageInput* mapped = context.input("laser_map")) {
    in.laser_map = mapped->artifact.path("map.txt");
    in.laser_map_scans =
        scan_poses_from_json(nlohmann::json::parse(read_file(mapped->artifact.path("scan_poses.json"))));
  }
  return in;
}

nlohmann::json save(const PosesResult& result, const StageContext& context, ArtifactWriter& out) {
  const std::string folder = context.stage.id + "/";
  if (!result.scans.empty()) {  // method laser: in the frame of the poses (anchored or the map's)
    out.write("scan_poses.json", to_json(result.scans).dump(1));
    Trajectory robot;
    for (const auto& s : result.scans)
      if (s.valid) robot.push_back({s.timestamp, to_pose3(s.T_map_robot)});
    out.write("robot_trajectory.txt", format_tum_trajectory(robot));
    out.publish("robot_trajectory.txt", folder + "robot_trajectory.txt", "robot_trajectory");
  }
  out.write_pieces("poses.json", [&](const PieceSink& sink) { poses_text(result.poses, sink); });
  std::map<std::string, Trajectory> by_sensor;
  nlohmann::json flagged = nlohmann::json::array();
  for (const auto& p : result.poses) {
    if (p.valid)
      by_sensor[p.sensor].push_back({p.timestamp, p.T_world_sensor});
    else
      flagged.push_back({{"observation", p.observation}, {"sensor", p.sensor}, {"flag", p.flag}});
  }
  // Every sensor of the recording gets its file, empty when none of its observations has a pose.
  for (const auto& sensor : result.sensors) {
    const std::string name = "trajectory_" + sensor + ".txt";
    out.write(name, format_tum_trajectory(by_sensor[sensor]));
    out.publish(name, folder + name, "trajectory", sensor);
  }
  nlohmann::json summary = result.figures;
  summary["observations"] = result.poses.size();
  summary["flagged"] = flagged;
  return summary;
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>& upstream, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const PosesConfig c = poses_params()->from_json(stage.params);
  if (c.method == PosesMethod::registration && c.registration.initial_guess == InitialGuess::trajectory &&
      c.guess_trajectory.empty())
    errors.push_back(doc.error_at(
        stage.pointer + "/params/registration/initial_guess",
        "stage '" + stage.id + "' (poses): registration.initial_guess trajectory needs 'guess_trajectory'"));
  if (c.anchor_fit == AnchorFit::all && c.anchor.empty() && !c.anchor_to_groundtruth)
    errors.push_back(
        doc.error_at(stage.pointer + "/params/anchor_fit",
                     "stage '" + stage.id + "' (poses): anchor_fit all needs 'anchor' (or anchor_to_groundtruth)"));
  if (c.method == PosesMethod::laser)
    if (const std::string problem = laser_settings_problem(c.laser); !problem.empty())
      errors.push_back(doc.error_at(stage.pointer + "/params", "stage '" + stage.id + "' (poses): laser." + problem));
  if (c.method == PosesMethod::laser && c.map.empty() && upstream.find("laser_map") == upstream.end())
    errors.push_back(
        doc.error_at(stage.pointer + "/params/method", "stage '" + stage.id +
                                                           "' (poses): method laser needs a map: a laser_map stage "
                                                           "upstream or 'map' (the map.txt of a laser_map run)"));
  if (!c.trajectory.empty() || c.method != PosesMethod::trajectory) return;
  auto source = upstream.find("source");
  if (source == upstream.end()) return;
  const auto& p = source->second->params;
  const bool has_truth = p.value("format", "") == "synthetic" ||
                         (p.value("path", "") != "" && fs::exists(fs::path(p.value("path", "")) / "groundtruth.txt"));
  if (!has_truth)
    errors.push_back(doc.error_at(stage.pointer + "/params",
                                  "stage '" + stage.id + "' (poses): give 'trajectory'; the recording of stage '" +
                                      source->second->id + "' has no groundtruth.txt"));
}

}  // namespace

StageKind poses_kind() {
  // 9: loop closures weighted by the links they span (registration poses change)
  return make_stage_kind({"poses", poses_params(), {"source", "calibrate"}, {"laser_map"}, check}, 9, files_read,
                         typed_stage(poses_params(), load, run_poses, save));
}

}  // namespace olt
