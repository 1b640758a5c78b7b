// `poses`: the 6-DoF pose of every RGB-D observation. Method `trajectory` imports a TUM-format
// trajectory (the job's file, or the recording's own ground truth) and interpolates it.
#include "olt/core/error.h"
#include "olt/formats/tum.h"
#include "olt/poses/trajectory_poses.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"

namespace olt {
namespace {

struct PosesConfig {
  std::string method = "trajectory";  ///< trajectory
  std::string trajectory;             ///< TUM trajectory file; default: the recording's ground truth
  std::string frame = "sensor";       ///< the trajectory gives T_world_sensor (sensor) or T_world_robot (robot)
  double max_gap_s = 0.05;            ///< largest time to the nearest trajectory sample, seconds
};

std::shared_ptr<const Params<PosesConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<PosesConfig>>();
    t->choice("method", &PosesConfig::method, {"trajectory"}, "how poses are found")
        .path("trajectory", &PosesConfig::trajectory, true,
              "TUM trajectory file; default: the recording's ground truth")
        .choice("frame", &PosesConfig::frame, {"sensor", "robot"}, "frame whose pose the trajectory gives")
        .number("max_gap_s", &PosesConfig::max_gap_s, positive(), "largest time to the nearest sample, seconds");
    return t;
  }();
  return p;
}

std::vector<fs::path> files_read(const StageDecl& stage) {
  const PosesConfig c = params()->from_json(stage.params);
  if (c.trajectory.empty()) return {};
  parse_tum_trajectory(c.trajectory, read_file(c.trajectory));  // bad input is found before anything runs
  return {c.trajectory};
}

void run(StageRun& run) {
  const PosesConfig c = params()->from_json(run.stage.params);
  const Recording recording = load_recording(*run.input("source"));
  const Calibration calibration = load_calibration(*run.input("calibrate"));
  const std::string file = c.trajectory.empty() ? recording.groundtruth : c.trajectory;
  if (file.empty()) throw InputError("stage '" + run.stage.id + "'", "no trajectory given and the recording has none");
  const Trajectory trajectory = parse_tum_trajectory(file, read_file(file));
  const auto poses =
      poses_from_trajectory(recording.observations, trajectory, calibration, {c.max_gap_s, c.frame == "robot"});
  run.write("poses.json", to_json(poses).dump(1));

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
    run.write(name, format_tum_trajectory(by_sensor[s.id]));
    run.publish(name, run.stage.id + "/" + name, "trajectory", s.id);
  }
  run.summary = {{"observations", poses.size()}, {"flagged", flagged}};
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>& upstream, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const PosesConfig c = params()->from_json(stage.params);
  if (!c.trajectory.empty()) return;
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

StageKind poses_kind() { return {{"poses", params(), {"source", "calibrate"}, {}, check}, 1, files_read, run}; }

}  // namespace olt
