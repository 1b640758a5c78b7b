// `poses`: the 6-DoF pose of every RGB-D observation. Method `trajectory` imports a TUM-format
// trajectory (the job's file, or the recording's own ground truth) and interpolates it.
#include <algorithm>

#include "olt/core/error.h"
#include "olt/core/image.h"
#include "olt/formats/tum.h"
#include "olt/poses/registration_poses.h"
#include "olt/poses/trajectory_poses.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"

namespace olt {
namespace {

struct PosesConfig {
  std::string method = "trajectory";  ///< trajectory | registration
  // method: trajectory
  std::string trajectory;        ///< TUM trajectory file; default: the recording's ground truth
  std::string frame = "sensor";  ///< the trajectory gives T_world_sensor (sensor) or T_world_robot (robot)
  double max_gap_s = 0.05;       ///< largest time to the nearest trajectory sample, seconds
  // method: registration
  RegistrationPosesConfig registration;  ///< every setting and its default lives there
  std::string guess_trajectory;          ///< initial_guess trajectory: TUM file of robot poses (e.g. odometry)
  std::string anchor;  ///< TUM trajectory of the first observation's sensor pose (e.g. a ground truth); default: robot
                       ///< at the origin
  bool anchor_to_groundtruth = false;  ///< take that pose from the recording's own ground truth instead
};

// Accessors binding the params table to the nested registration settings.
template <class T>
auto reg(T RegistrationPosesConfig::*m) {
  return [m](PosesConfig& c) -> T& { return c.registration.*m; };
}
template <class T>
auto solver(T RegistrationSetting::*m) {
  return [m](PosesConfig& c) -> T& { return c.registration.registration.*m; };
}

std::shared_ptr<const Params<PosesConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<PosesConfig>>();
    t->choice("method", &PosesConfig::method, {"trajectory", "registration"}, "how poses are found")
        .path("trajectory", &PosesConfig::trajectory, true,
              "TUM trajectory file; default: the recording's ground truth")
        .choice("frame", &PosesConfig::frame, {"sensor", "robot"}, "frame whose pose the trajectory gives")
        .number("max_gap_s", &PosesConfig::max_gap_s, positive(), "largest time to the nearest sample, seconds")
        .choice("algorithm", solver(&RegistrationSetting::method), {"gicp", "icp"},
                "registration: gicp or point-to-plane icp")
        .number("max_correspondence_m", solver(&RegistrationSetting::max_correspondence_m), positive(),
                "farthest correspondence, metres")
        .integer("max_iterations", solver(&RegistrationSetting::max_iterations), between(1, 1000),
                 "Gauss-Newton iterations at most")
        .number("translation_eps_m", solver(&RegistrationSetting::translation_eps_m), positive(),
                "convergence threshold, metres")
        .number("rotation_eps_rad", solver(&RegistrationSetting::rotation_eps_rad), positive(),
                "convergence threshold, radians")
        .number("voxel_size_m", reg(&RegistrationPosesConfig::voxel_size_m), between(0.001, 1),
                "registration voxel, metres")
        .integer("pixel_stride", reg(&RegistrationPosesConfig::pixel_stride), between(1, 32),
                 "every n-th pixel per direction")
        .number("min_depth_m", reg(&RegistrationPosesConfig::min_depth_m), non_negative(),
                "registration depth range, metres")
        .number("max_depth_m", reg(&RegistrationPosesConfig::max_depth_m), positive(),
                "registration depth range, metres")
        .integer("covariance_neighbors", reg(&RegistrationPosesConfig::covariance_neighbors), between(5, 100),
                 "k for covariances")
        .boolean("smoothing", reg(&RegistrationPosesConfig::smoothing), "bilateral depth smoothing before registration")
        .number("sigma_s_px", reg(&RegistrationPosesConfig::sigma_s_px), between(0.5, 20),
                "smoothing spatial sigma, pixels")
        .number("sigma_r_m", reg(&RegistrationPosesConfig::sigma_r_m), positive(), "smoothing range sigma, metres")
        .choice("memory", reg(&RegistrationPosesConfig::memory), {"previous", "local_map"}, "registration target")
        .integer("memory_size", reg(&RegistrationPosesConfig::memory_size), between(1, 1000),
                 "local_map size, observations")
        .number("key_distance_m", reg(&RegistrationPosesConfig::key_distance_m), non_negative(),
                "key pose distance, metres (0 = off)")
        .number("key_angle_deg", reg(&RegistrationPosesConfig::key_angle_deg), non_negative(),
                "key pose angle, degrees (0 = off)")
        .number("key_max_interval_s", reg(&RegistrationPosesConfig::key_max_interval_s), positive(),
                "key pose at least this often, s")
        .choice("initial_guess", reg(&RegistrationPosesConfig::initial_guess),
                {"constant_velocity", "previous_pose", "trajectory"}, "registration guess")
        .path("guess_trajectory", &PosesConfig::guess_trajectory, true,
              "initial_guess trajectory: TUM file of robot poses (e.g. odometry)")
        .number("max_rmse_m", reg(&RegistrationPosesConfig::max_rmse_m), positive(),
                "flag above this inlier RMSE, metres")
        .number("min_inlier_ratio", reg(&RegistrationPosesConfig::min_inlier_ratio), between(0, 1),
                "flag below this inlier fraction")
        .path("anchor", &PosesConfig::anchor, true,
              "TUM trajectory of the first observation's sensor pose (e.g. a ground truth)")
        .boolean("anchor_to_groundtruth", &PosesConfig::anchor_to_groundtruth,
                 "take the first observation's pose from the recording's ground truth");
    return t;
  }();
  return p;
}

std::vector<fs::path> files_read(const StageDecl& stage) {
  const PosesConfig c = params()->from_json(stage.params);
  std::vector<fs::path> files;
  for (const std::string& file : {c.trajectory, c.anchor, c.guess_trajectory}) {
    if (file.empty()) continue;
    parse_tum_trajectory(file, read_file(file));  // bad input is found before anything runs
    files.push_back(file);
  }
  return files;
}

std::vector<ObservationPose> registered_poses(const PosesConfig& c, const Recording& recording,
                                              const Calibration& calibration) {
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
    T_world_robot_first = T_world_robot_first * calibration.at(first.sensor).T_robot_sensor.inverse();
  }
  RegistrationPosesConfig config = c.registration;
  if (!c.guess_trajectory.empty())
    config.guess_trajectory = parse_tum_trajectory(c.guess_trajectory, read_file(c.guess_trajectory));
  RegistrationOdometry odometry(calibration, config, T_world_robot_first);
  for (const auto& o : recording.observations) odometry.add(o, read_png_u16(o.depth.path));
  return odometry.finish();
}

void run(StageRun& run) {
  const PosesConfig c = params()->from_json(run.stage.params);
  const Recording recording = load_recording(*run.input("source"));
  const Calibration calibration = load_calibration(*run.input("calibrate"));
  std::vector<ObservationPose> poses;
  if (c.method == "registration") {
    poses = registered_poses(c, recording, calibration);
  } else {
    const std::string file = c.trajectory.empty() ? recording.groundtruth : c.trajectory;
    if (file.empty())
      throw InputError("stage '" + run.stage.id + "'", "no trajectory given and the recording has none");
    const Trajectory trajectory = parse_tum_trajectory(file, read_file(file));
    poses = poses_from_trajectory(recording.observations, trajectory, calibration, {c.max_gap_s, c.frame == "robot"});
    // Some observations outside the trajectory are flagged; none inside it is a wrong file.
    if (!poses.empty() && std::none_of(poses.begin(), poses.end(), [](const auto& p) { return p.valid; }))
      throw InputError(file, "covers none of the " + std::to_string(poses.size()) + " observations (trajectory " +
                                 (trajectory.empty() ? std::string("empty")
                                                     : std::to_string(trajectory.front().timestamp) + " to " +
                                                           std::to_string(trajectory.back().timestamp) + " s") +
                                 ", observations " + std::to_string(recording.observations.front().timestamp) + " to " +
                                 std::to_string(recording.observations.back().timestamp) + " s)");
  }
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
  if (c.method == "registration" && c.registration.initial_guess == "trajectory" && c.guess_trajectory.empty())
    errors.push_back(
        doc.error_at(stage.pointer + "/params/initial_guess",
                     "stage '" + stage.id + "' (poses): initial_guess trajectory needs 'guess_trajectory'"));
  if (!c.trajectory.empty() || c.method != "trajectory") return;
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

StageKind poses_kind() { return {{"poses", params(), {"source", "calibrate"}, {}, check}, 4, files_read, run}; }

}  // namespace olt
