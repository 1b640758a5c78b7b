// `poses`: the 6-DoF pose of every RGB-D observation. Method `trajectory` imports a TUM-format
// trajectory (the job's file, or the recording's own ground truth) and interpolates it;
// `registration` aligns the observations' depth; `laser` localizes the robot's laser scans in a
// 2D map and interpolates the robot pose at each observation, optionally refined by registration.
// This file: the stage's files, its run and its checks; the config in poses_config.h, the methods
// in poses_registration.cpp and poses_laser.cpp.
#include <algorithm>

#include "olt/core/error.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/poses/trajectory_poses.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
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

nlohmann::json run(const StageContext& ctx, ArtifactWriter& out) {
  const PosesConfig c = poses_params()->from_json(ctx.stage.params);
  const Recording recording = load_recording(ctx.need("source"));
  const Calibration calibration = load_calibration(ctx.need("calibrate"));
  std::vector<ObservationPose> poses;
  nlohmann::json summary = nlohmann::json::object();
  if (c.method == PosesMethod::registration) {
    poses = registered_poses(c, recording, calibration, summary);
    if (c.anchor_fit == AnchorFit::all) fit_to_anchor(c, recording, calibration, poses);
  } else if (c.method == PosesMethod::laser) {
    poses = laser_poses(ctx, out, summary, c, recording, calibration);
  } else {
    const std::string file = c.trajectory.empty() ? recording.groundtruth : c.trajectory;
    if (file.empty())
      throw InputError("stage '" + ctx.stage.id + "'", "no trajectory given and the recording has none");
    const Trajectory trajectory = parse_tum_trajectory(file, read_file(file));
    const bool robot_frame =
        c.frame == TrajectoryFrame::robot || (c.trajectory.empty() && recording.groundtruth_frame == "robot");
    poses = poses_from_trajectory(recording.observations, trajectory, calibration, {c.max_gap_s, robot_frame});
    // Some observations outside the trajectory are flagged; none inside it is a wrong file.
    if (!poses.empty() && std::none_of(poses.begin(), poses.end(), [](const auto& p) { return p.valid; }))
      throw InputError(file, "covers none of the " + std::to_string(poses.size()) + " observations (trajectory " +
                                 (trajectory.empty() ? std::string("empty")
                                                     : std::to_string(trajectory.front().timestamp) + " to " +
                                                           std::to_string(trajectory.back().timestamp) + " s") +
                                 ", observations " + std::to_string(recording.observations.front().timestamp) + " to " +
                                 std::to_string(recording.observations.back().timestamp) + " s)");
  }
  out.write("poses.json", to_json(poses).dump(1));

  std::map<std::string, Trajectory> by_sensor;
  nlohmann::json flagged = nlohmann::json::array();
  for (const auto& p : poses) {
    if (p.valid)
      by_sensor[p.sensor].push_back({p.timestamp, p.T_world_sensor});
    else
      flagged.push_back({{"observation", p.observation}, {"sensor", p.sensor}, {"flag", p.flag}});
  }
  for (const auto& s : recording.sensors) {
    const std::string name = "trajectory_" + s.id + ".txt";
    out.write(name, format_tum_trajectory(by_sensor[s.id]));
    out.publish(name, ctx.stage.id + "/" + name, "trajectory", s.id);
  }
  summary["observations"] = poses.size();
  summary["flagged"] = flagged;
  return summary;
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>& upstream, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const PosesConfig c = poses_params()->from_json(stage.params);
  if (c.method == PosesMethod::registration && c.registration.initial_guess == InitialGuess::trajectory &&
      c.guess_trajectory.empty())
    errors.push_back(
        doc.error_at(stage.pointer + "/params/initial_guess",
                     "stage '" + stage.id + "' (poses): initial_guess trajectory needs 'guess_trajectory'"));
  if (c.anchor_fit == AnchorFit::all && c.anchor.empty() && !c.anchor_to_groundtruth)
    errors.push_back(
        doc.error_at(stage.pointer + "/params/anchor_fit",
                     "stage '" + stage.id + "' (poses): anchor_fit all needs 'anchor' (or anchor_to_groundtruth)"));
  if (c.method == PosesMethod::laser)
    if (const std::string problem = laser_settings_problem(c.laser); !problem.empty())
      errors.push_back(doc.error_at(stage.pointer + "/params", "stage '" + stage.id + "' (poses): laser_" + problem));
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
  return make_stage_kind({"poses", poses_params(), {"source", "calibrate"}, {"laser_map"}, check}, 9, files_read, run);
}

}  // namespace olt
