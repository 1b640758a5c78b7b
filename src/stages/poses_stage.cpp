// `poses`: the 6-DoF pose of every RGB-D observation. Method `trajectory` imports a TUM-format
// trajectory (the job's file, or the recording's own ground truth) and interpolates it;
// `registration` aligns the observations' depth; `laser` localizes the robot's laser scans in a
// 2D map and interpolates the robot pose at each observation, optionally refined by registration.
#include <algorithm>
#include <atomic>

#include "olt/core/error.h"
#include "olt/core/image.h"
#include "olt/core/parallel.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/poses/consistency.h"
#include "olt/poses/laser_poses.h"
#include "olt/poses/registration_poses.h"
#include "olt/poses/trajectory_poses.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
#include "olt/stages/laser.h"

namespace olt {
namespace {

struct PosesConfig {
  std::string method = "trajectory";  ///< trajectory | registration | laser
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
  /// first: the first observation placed by the anchor; all: the registered trajectory moved by the
  /// rigid transform that fits it best to the anchor at every observation of that sensor it covers
  std::string anchor_fit = "first";
  ConsistencySetting consistency;  ///< memory keyframes: every observation scored against the keyframes' scene
  // method: laser
  LaserMapSettings laser;            ///< localization: scan matching and ranges (laser_* params)
  std::string map;                   ///< map.txt of a laser_map run; default: the laser_map stage upstream
  std::vector<double> initial_pose;  ///< x y (m) yaw (deg): the robot at the first scan, in the map
  double max_scan_gap_s = 1.0;       ///< flag observations between scans farther apart, seconds
  std::string refine = "none";       ///< none | registration (laser poses as its guess and anchor)
};

// Accessors binding the params table to the nested registration settings.
template <class T>
auto reg(T RegistrationPosesConfig::*m) {
  return [m](PosesConfig& c) -> T& { return c.registration.*m; };
}
template <class T>
auto cons(T ConsistencySetting::*m) {
  return [m](PosesConfig& c) -> T& { return c.consistency.*m; };
}
template <class T>
auto solver(T RegistrationSetting::*m) {
  return [m](PosesConfig& c) -> T& { return c.registration.registration.*m; };
}

std::shared_ptr<const Params<PosesConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<PosesConfig>>();
    t->choice("method", &PosesConfig::method, {"trajectory", "registration", "laser"}, "how poses are found")
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
        .number("photometric_weight", reg(&RegistrationPosesConfig::photometric_weight), non_negative(),
                "colour term weight (0 = depth only)")
        .integer("photometric_halvings", reg(&RegistrationPosesConfig::photometric_halvings), between(0, 2),
                 "colour term on images halved this many times")
        .number("photometric_min_gradient", reg(&RegistrationPosesConfig::photometric_min_gradient), non_negative(),
                "colour term: least intensity gradient per reduced pixel")
        .number("photometric_huber", reg(&RegistrationPosesConfig::photometric_huber), positive(),
                "colour term: Huber threshold, intensity in [0, 1]")
        .boolean("smoothing", reg(&RegistrationPosesConfig::smoothing), "bilateral depth smoothing before registration")
        .number("sigma_s_px", reg(&RegistrationPosesConfig::sigma_s_px), between(0.5, 20),
                "smoothing spatial sigma, pixels")
        .number("sigma_r_m", reg(&RegistrationPosesConfig::sigma_r_m), positive(), "smoothing range sigma, metres")
        .choice("memory", reg(&RegistrationPosesConfig::memory), {"keyframes", "previous", "local_map"},
                "registration target: keyframes with loop closures, the previous observation, or a local map")
        .number("keyframe_distance_m", reg(&RegistrationPosesConfig::keyframe_distance_m), positive(),
                "keyframes: a new one after moving this far from the last, metres")
        .number("keyframe_angle_deg", reg(&RegistrationPosesConfig::keyframe_angle_deg), positive(),
                "keyframes: ... or turning this much, degrees")
        .integer("loop_candidates", reg(&RegistrationPosesConfig::loop_candidates), between(0, 100),
                 "keyframes: earlier keyframes each new one is registered against (0 = no loop closure)")
        .number("loop_max_distance_m", reg(&RegistrationPosesConfig::loop_max_distance_m), positive(),
                "keyframes: loop candidates' camera centres at most this far apart, metres")
        .number("loop_max_angle_deg", reg(&RegistrationPosesConfig::loop_max_angle_deg), between(0, 180),
                "keyframes: ... and optical axes at most this far apart, degrees")
        .number("loop_min_inlier_ratio", reg(&RegistrationPosesConfig::loop_min_inlier_ratio), between(0, 1),
                "keyframes: a loop closure matches at least this fraction of points")
        .number("loop_max_correction_m", reg(&RegistrationPosesConfig::loop_max_correction_m), positive(),
                "keyframes: ... and moves a keyframe at most this far from its estimate, metres")
        .number("loop_max_correction_deg", reg(&RegistrationPosesConfig::loop_max_correction_deg), positive(),
                "keyframes: ... and turns it at most this much, degrees")
        .number("consistency_distance_m", cons(&ConsistencySetting::distance_m), positive(),
                "keyframes: a depth point within this distance of the scene agrees with it, metres")
        .number("min_consistency", cons(&ConsistencySetting::min_fraction), between(0, 1),
                "keyframes: flag observations with a smaller fraction of agreeing points")
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
        .number("max_correction_m", reg(&RegistrationPosesConfig::max_correction_m), positive(),
                "refine: keep the laser pose where registration moves it farther, m")
        .number("max_correction_deg", reg(&RegistrationPosesConfig::max_correction_deg), positive(),
                "refine: ... or turns it more, degrees")
        .path("anchor", &PosesConfig::anchor, true,
              "TUM trajectory of the first observation's sensor pose (e.g. a ground truth)")
        .choice("anchor_fit", &PosesConfig::anchor_fit, {"first", "all"},
                "registration: place the trajectory by the anchor's first pose, or fit it to all of them")
        .boolean("anchor_to_groundtruth", &PosesConfig::anchor_to_groundtruth,
                 "take the first observation's pose from the recording's ground truth")
        .path("map", &PosesConfig::map, true, "laser: map.txt of a laser_map run; default: the laser_map stage")
        .numbers("initial_pose", &PosesConfig::initial_pose, 3,
                 "laser: x y (m) yaw (deg) of the robot at the first scan")
        .number("max_scan_gap_s", &PosesConfig::max_scan_gap_s, positive(),
                "laser: flag observations between scans farther apart, s")
        .choice("refine", &PosesConfig::refine, {"none", "registration"}, "laser: refine by registration");
    add_laser_params(
        *t, [](PosesConfig& c) -> LaserMapSettings& { return c.laser; }, "laser_");
    return t;
  }();
  return p;
}

std::vector<fs::path> files_read(const StageDecl& stage) {
  const PosesConfig c = params()->from_json(stage.params);
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

// Reads the observation's colour image when the registration asks for it.
RegistrationOdometry::ColorLoader color_of(const Observation& o) {
  return [&o] { return o.color ? read_png_bgr(o.color->path) : cv::Mat(); };
}

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
        surface.score(odometry.sample_points(o, read_png_u16(o.depth.path)), p.T_world_sensor, c.consistency);
    p.quality["consistency"] = {
        {"fraction", score.fraction}, {"coverage", score.coverage}, {"rmse_m", score.rmse_m}, {"points", score.points}};
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
  for (const auto& o : recording.observations) odometry.add(o, read_png_u16(o.depth.path), color_of(o));
  std::vector<ObservationPose> poses = odometry.finish();
  if (config.memory != "keyframes") return poses;
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

PointMap2D load_map(const std::string& file) {
  const PointMapText text = parse_point_map(file, read_file(file));
  PointMap2D map(1e-4);  // the file's points are already thinned
  map.add(text.points, text.normals);
  map.build();
  return map;
}

// Laser poses: the scans localized in the map, the robot pose interpolated at each observation;
// with refine, registration from there (the laser's motion as its guess, its first pose as anchor).
std::vector<ObservationPose> laser_poses(StageRun& run, const PosesConfig& c, const Recording& recording,
                                         const Calibration& calibration) {
  const LaserData laser = load_laser_data(recording, run.stage.id);
  const StageInput* mapped = run.input("laser_map");
  Pose2 start = Pose2::Identity();
  if (!c.initial_pose.empty()) {
    start = pose2(c.initial_pose[0], c.initial_pose[1], c.initial_pose[2] * M_PI / 180);
  } else if (mapped && c.map.empty()) {  // the map's own first pose
    const auto own = scan_poses_from_json(nlohmann::json::parse(read_file(mapped->artifact.dir / "scan_poses.json")));
    if (!own.empty()) start = own.front().T_map_robot;
  }
  const PointMap2D map = load_map(c.map.empty() ? (mapped->artifact.dir / "map.txt").string() : c.map);
  std::vector<ScanPose> scans = localize_scans(map, laser.scans, laser.odometry, c.laser, start);
  // Anchored: the map placed in the ground truth's world so that the robot at the first scan is where
  // the ground truth puts it (boxes drawn in that world then apply).
  const auto anchor = std::find_if(scans.begin(), scans.end(), [](const ScanPose& s) { return s.valid; });
  if (c.anchor_to_groundtruth && anchor != scans.end()) {  // on the first scan localized
    if (recording.groundtruth.empty() || recording.groundtruth_frame != "robot")
      throw InputError("stage '" + run.stage.id + "'",
                       "anchor_to_groundtruth with method laser needs the recording's ground truth of the robot");
    const Trajectory truth = parse_tum_trajectory(recording.groundtruth, read_file(recording.groundtruth));
    Pose T_world_robot;
    double gap;
    if (!interpolate_trajectory(truth, anchor->timestamp, &T_world_robot, &gap))
      throw InputError(recording.groundtruth, "does not cover the time of the first scan localized");
    const Pose2 T_world_map = to_pose2(T_world_robot) * anchor->T_map_robot.inverse();
    for (auto& s : scans) s.T_map_robot = T_world_map * s.T_map_robot;
  }
  run.write("scan_poses.json", to_json(scans).dump(1));  // in the frame of the poses (anchored or the map's)
  Trajectory robot;
  for (const auto& s : scans)
    if (s.valid) robot.push_back({s.timestamp, to_pose3(s.T_map_robot)});
  run.write("robot_trajectory.txt", format_tum_trajectory(robot));
  run.publish("robot_trajectory.txt", run.stage.id + "/robot_trajectory.txt", "robot_trajectory");
  run.summary["scans"] = scans.size();
  run.summary["scans_failed"] = std::count_if(scans.begin(), scans.end(), [](const ScanPose& s) { return !s.valid; });

  LaserPoses placed = poses_from_scans(recording.observations, scans, calibration, c.max_scan_gap_s);
  run.summary["observations_outside_scans"] = placed.outside_scans;
  run.summary["observations_in_scan_gaps"] = placed.in_scan_gaps;
  run.summary["observations_next_to_failed_scans"] = placed.next_to_failed_scans;
  std::vector<ObservationPose>& poses = placed.poses;
  if (c.refine != "registration") return poses;
  // Each observation the laser placed is registered from its laser pose against the last ones at
  // theirs (the registration settings above; memory: previous or local_map).
  RegistrationOdometry refine(calibration, c.registration, Pose::Identity());
  std::vector<size_t> refined_index;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (!poses[i].valid) continue;
    const Observation& o = recording.observations[i];
    refine.add(o, read_png_u16(o.depth.path), color_of(o), &poses[i].T_world_sensor);
    refined_index.push_back(i);
  }
  const std::vector<ObservationPose> refined = refine.finish();
  for (size_t k = 0; k < refined.size(); ++k) {
    ObservationPose& p = poses[refined_index[k]];
    p.quality = {{"laser", p.quality}, {"registration", refined[k].quality}};
    p.T_world_sensor = refined[k].T_world_sensor;
    p.valid = refined[k].valid;
    p.flag = refined[k].flag;
  }
  return poses;
}

void run(StageRun& run) {
  const PosesConfig c = params()->from_json(run.stage.params);
  const Recording recording = load_recording(*run.input("source"));
  const Calibration calibration = load_calibration(*run.input("calibrate"));
  std::vector<ObservationPose> poses;
  if (c.method == "registration") {
    poses = registered_poses(c, recording, calibration, run.summary);
    if (c.anchor_fit == "all") fit_to_anchor(c, recording, calibration, poses);
  } else if (c.method == "laser") {
    poses = laser_poses(run, c, recording, calibration);
  } else {
    const std::string file = c.trajectory.empty() ? recording.groundtruth : c.trajectory;
    if (file.empty())
      throw InputError("stage '" + run.stage.id + "'", "no trajectory given and the recording has none");
    const Trajectory trajectory = parse_tum_trajectory(file, read_file(file));
    const bool robot_frame = c.frame == "robot" || (c.trajectory.empty() && recording.groundtruth_frame == "robot");
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
  run.summary["observations"] = poses.size();
  run.summary["flagged"] = flagged;
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>& upstream, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const PosesConfig c = params()->from_json(stage.params);
  if (c.method == "registration" && c.registration.initial_guess == "trajectory" && c.guess_trajectory.empty())
    errors.push_back(
        doc.error_at(stage.pointer + "/params/initial_guess",
                     "stage '" + stage.id + "' (poses): initial_guess trajectory needs 'guess_trajectory'"));
  if (c.anchor_fit == "all" && c.anchor.empty() && !c.anchor_to_groundtruth)
    errors.push_back(
        doc.error_at(stage.pointer + "/params/anchor_fit",
                     "stage '" + stage.id + "' (poses): anchor_fit all needs 'anchor' (or anchor_to_groundtruth)"));
  if (c.method == "laser")
    if (const std::string problem = laser_settings_problem(c.laser); !problem.empty())
      errors.push_back(doc.error_at(stage.pointer + "/params", "stage '" + stage.id + "' (poses): laser_" + problem));
  if (c.method == "laser" && c.map.empty() && upstream.find("laser_map") == upstream.end())
    errors.push_back(
        doc.error_at(stage.pointer + "/params/method", "stage '" + stage.id +
                                                           "' (poses): method laser needs a map: a laser_map stage "
                                                           "upstream or 'map' (the map.txt of a laser_map run)"));
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

StageKind poses_kind() {
  // 9: loop closures weighted by the links they span (registration poses change)
  return {{"poses", params(), {"source", "calibrate"}, {"laser_map"}, check}, 9, files_read, run};
}

}  // namespace olt
