// `poses`: the 6-DoF pose of every RGB-D observation. Method `trajectory` imports a TUM-format
// trajectory (the job's file, or the recording's own ground truth) and interpolates it.
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
  // method: registration (defaults in RegistrationPosesConfig)
  std::string algorithm = "gicp";                   ///< gicp | icp (point-to-plane)
  double max_correspondence_m = 0.1;                ///< farthest correspondence, metres
  int max_iterations = 30;                          ///< Gauss-Newton iterations at most
  double translation_eps_m = 1e-4;                  ///< convergence: update smaller than this, metres
  double rotation_eps_rad = 1e-4;                   ///< convergence: update smaller than this, radians
  double voxel_size_m = 0.02;                       ///< registration voxel, metres
  int pixel_stride = 2;                             ///< back-project every n-th pixel per direction
  double min_depth_m = 0.3;                         ///< registration depth range, metres
  double max_depth_m = 4.0;                         ///< registration depth range, metres
  int covariance_neighbors = 10;                    ///< k for covariances and normals
  bool smoothing = false;                           ///< bilateral depth smoothing before registration
  double sigma_s_px = 3;                            ///< smoothing spatial sigma, pixels
  double sigma_r_m = 0.05;                          ///< smoothing range sigma, metres
  std::string memory = "previous";                  ///< previous | local_map
  int memory_size = 5;                              ///< local_map size, observations
  double key_distance_m = 0;                        ///< key poses: distance threshold, metres (0 = off)
  double key_angle_deg = 0;                         ///< key poses: angle threshold, degrees (0 = off)
  double key_max_interval_s = 0.5;                  ///< key poses: register at least this often, seconds
  std::string initial_guess = "constant_velocity";  ///< constant_velocity | previous_pose | trajectory
  std::string guess_trajectory;   ///< initial_guess trajectory: TUM file of robot poses (e.g. odometry)
  double max_rmse_m = 0.05;       ///< flag above this inlier RMSE, metres
  double min_inlier_ratio = 0.3;  ///< flag below this inlier fraction
  std::string anchor;             ///< TUM trajectory giving the robot pose at the first observation (default: identity)
  bool anchor_to_groundtruth = false;  ///< take that pose from the recording's own ground truth instead
};

RegistrationPosesConfig registration_config(const PosesConfig& c) {
  RegistrationPosesConfig r;
  r.registration = {c.algorithm, c.max_correspondence_m, c.max_iterations, c.translation_eps_m, c.rotation_eps_rad};
  r.voxel_size_m = c.voxel_size_m;
  r.pixel_stride = c.pixel_stride;
  r.min_depth_m = c.min_depth_m;
  r.max_depth_m = c.max_depth_m;
  r.covariance_neighbors = c.covariance_neighbors;
  r.smoothing = c.smoothing;
  r.sigma_s_px = c.sigma_s_px;
  r.sigma_r_m = c.sigma_r_m;
  r.memory = c.memory;
  r.memory_size = c.memory_size;
  r.key_distance_m = c.key_distance_m;
  r.key_angle_deg = c.key_angle_deg;
  r.key_max_interval_s = c.key_max_interval_s;
  r.initial_guess = c.initial_guess;
  if (!c.guess_trajectory.empty())
    r.guess_trajectory = parse_tum_trajectory(c.guess_trajectory, read_file(c.guess_trajectory));
  r.max_rmse_m = c.max_rmse_m;
  r.min_inlier_ratio = c.min_inlier_ratio;
  return r;
}

std::shared_ptr<const Params<PosesConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<PosesConfig>>();
    t->choice("method", &PosesConfig::method, {"trajectory", "registration"}, "how poses are found")
        .path("trajectory", &PosesConfig::trajectory, true,
              "TUM trajectory file; default: the recording's ground truth")
        .choice("frame", &PosesConfig::frame, {"sensor", "robot"}, "frame whose pose the trajectory gives")
        .number("max_gap_s", &PosesConfig::max_gap_s, positive(), "largest time to the nearest sample, seconds")
        .choice("algorithm", &PosesConfig::algorithm, {"gicp", "icp"}, "registration: gicp or point-to-plane icp")
        .number("max_correspondence_m", &PosesConfig::max_correspondence_m, positive(),
                "farthest correspondence, metres")
        .integer("max_iterations", &PosesConfig::max_iterations, between(1, 1000), "Gauss-Newton iterations at most")
        .number("translation_eps_m", &PosesConfig::translation_eps_m, positive(), "convergence threshold, metres")
        .number("rotation_eps_rad", &PosesConfig::rotation_eps_rad, positive(), "convergence threshold, radians")
        .number("voxel_size_m", &PosesConfig::voxel_size_m, between(0.001, 1), "registration voxel, metres")
        .integer("pixel_stride", &PosesConfig::pixel_stride, between(1, 32), "every n-th pixel per direction")
        .number("min_depth_m", &PosesConfig::min_depth_m, non_negative(), "registration depth range, metres")
        .number("max_depth_m", &PosesConfig::max_depth_m, positive(), "registration depth range, metres")
        .integer("covariance_neighbors", &PosesConfig::covariance_neighbors, between(5, 100), "k for covariances")
        .boolean("smoothing", &PosesConfig::smoothing, "bilateral depth smoothing before registration")
        .number("sigma_s_px", &PosesConfig::sigma_s_px, between(0.5, 20), "smoothing spatial sigma, pixels")
        .number("sigma_r_m", &PosesConfig::sigma_r_m, positive(), "smoothing range sigma, metres")
        .choice("memory", &PosesConfig::memory, {"previous", "local_map"}, "registration target")
        .integer("memory_size", &PosesConfig::memory_size, between(1, 1000), "local_map size, observations")
        .number("key_distance_m", &PosesConfig::key_distance_m, non_negative(), "key pose distance, metres (0 = off)")
        .number("key_angle_deg", &PosesConfig::key_angle_deg, non_negative(), "key pose angle, degrees (0 = off)")
        .number("key_max_interval_s", &PosesConfig::key_max_interval_s, positive(), "key pose at least this often, s")
        .choice("initial_guess", &PosesConfig::initial_guess, {"constant_velocity", "previous_pose", "trajectory"},
                "registration guess")
        .path("guess_trajectory", &PosesConfig::guess_trajectory, true,
              "initial_guess trajectory: TUM file of robot poses (e.g. odometry)")
        .number("max_rmse_m", &PosesConfig::max_rmse_m, positive(), "flag above this inlier RMSE, metres")
        .number("min_inlier_ratio", &PosesConfig::min_inlier_ratio, between(0, 1), "flag below this inlier fraction")
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
  RegistrationOdometry odometry(calibration, registration_config(c), T_world_robot_first);
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
  if (c.method == "registration" && c.initial_guess == "trajectory" && c.guess_trajectory.empty())
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

StageKind poses_kind() { return {{"poses", params(), {"source", "calibrate"}, {}, check}, 3, files_read, run}; }

}  // namespace olt
