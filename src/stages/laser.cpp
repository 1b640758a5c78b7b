#include "olt/stages/laser.h"

#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/formats/laser_text.h"

namespace olt {

LaserData load_laser_data(const Recording& recording, const std::string& stage) {
  if (recording.laser_scans.empty()) throw InputError("stage '" + stage + "'", "the recording has no 2D laser scans");
  LaserData d;
  d.scans = parse_laser_scans(recording.laser_scans, read_file(recording.laser_scans));
  if (!recording.odometry.empty()) d.odometry = parse_odometry(recording.odometry, read_file(recording.odometry));
  return d;
}

std::string laser_settings_problem(const LaserMapSettings& s) {
  if (s.matching.min_correspondence_m > s.matching.max_correspondence_m)
    return "min_correspondence_m is larger than max_correspondence_m";
  if (s.min_range_m >= s.max_range_m) return "min_range_m is not below max_range_m";
  return "";
}

namespace {

std::shared_ptr<const Params<ScanMatchSettings>> scan_match_params() {
  static auto p = [] {
    auto t = std::make_shared<Params<ScanMatchSettings>>();
    t->number("max_correspondence_m", &ScanMatchSettings::max_correspondence_m, between(0.001, 100),
              "first pass correspondence distance, m")
        .number("min_correspondence_m", &ScanMatchSettings::min_correspondence_m, between(0.001, 100),
                "last pass correspondence distance, m")
        .integer("max_iterations", &ScanMatchSettings::max_iterations, between(1, 1000), "iterations per pass")
        .number("huber_m", &ScanMatchSettings::huber_m, positive(), "robust threshold, m");
    return t;
  }();
  return p;
}

}  // namespace

std::shared_ptr<const Params<LaserMapSettings>> laser_localization_params() {
  static auto p = [] {
    auto t = std::make_shared<Params<LaserMapSettings>>();
    t->number("min_range_m", &LaserMapSettings::min_range_m, non_negative(), "nearer laser returns ignored, m")
        .number("max_range_m", &LaserMapSettings::max_range_m, positive(), "farther laser returns ignored, m")
        .nested("matching", &LaserMapSettings::matching, scan_match_params(), "scan matching")
        .number("max_rmse_m", &LaserMapSettings::max_rmse_m, positive(), "a scan match fails above this RMSE, m")
        .number("min_inlier_ratio", &LaserMapSettings::min_inlier_ratio, between(0, 1),
                "a scan match fails below this inlier fraction");
    return t;
  }();
  return p;
}

std::shared_ptr<const Params<LaserMapSettings>> laser_mapping_params() {
  static auto p = [] {
    auto t = std::make_shared<Params<LaserMapSettings>>();
    t->embed([](LaserMapSettings& s) -> LaserMapSettings& { return s; }, *laser_localization_params())
        .integer("local_keyframes", &LaserMapSettings::local_keyframes, between(1, 10000),
                 "tracking matches against this many recent keyframes")
        .number("key_distance_m", &LaserMapSettings::key_distance_m, between(0.01, 100),
                "a keyframe after moving this far, metres")
        .number("key_angle_deg", &LaserMapSettings::key_angle_deg, between(0.5, 180),
                "... or turning this much, degrees")
        .number("map_cell_m", &LaserMapSettings::map_cell_m, between(0.005, 1),
                "one map point per cell of this size, metres")
        .number("loop_radius_m", &LaserMapSettings::loop_radius_m, non_negative(),
                "loop closure search radius, metres (0 = off)")
        .integer("loop_min_keyframes", &LaserMapSettings::loop_min_keyframes, between(1, 100000),
                 "loop closure: at least this many keyframes back")
        .number("loop_min_inlier_ratio", &LaserMapSettings::loop_min_inlier_ratio, between(0, 1),
                "a loop match needs this inlier fraction")
        .number("loop_max_rmse_m", &LaserMapSettings::loop_max_rmse_m, positive(),
                "a loop match needs at most this RMSE, metres");
    return t;
  }();
  return p;
}

nlohmann::json to_json(const std::vector<ScanPose>& poses) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : poses)
    out.push_back({{"timestamp", p.timestamp},
                   {"pose", {p.T_map_robot.translation().x(), p.T_map_robot.translation().y(), heading(p.T_map_robot)}},
                   {"key", p.key},
                   {"valid", p.valid},
                   {"flag", p.flag},
                   {"quality",
                    {{"converged", p.match.converged},
                     {"iterations", p.match.iterations},
                     {"inliers", p.match.inliers},
                     {"inlier_ratio", p.match.inlier_ratio},
                     {"rmse_m", p.match.rmse_m}}}});
  return out;
}

std::vector<ScanPose> scan_poses_from_json(const nlohmann::json& j) {
  std::vector<ScanPose> poses;
  for (const auto& v : j) {
    ScanPose p;
    p.timestamp = v.at("timestamp");
    const auto& q = v.at("pose");
    p.T_map_robot = pose2(q.at(0), q.at(1), q.at(2));
    p.key = v.at("key");
    p.valid = v.at("valid");
    p.flag = v.at("flag");
    const auto& m = v.at("quality");
    p.match.converged = m.at("converged");
    p.match.iterations = m.at("iterations");
    p.match.inliers = m.at("inliers");
    p.match.inlier_ratio = m.at("inlier_ratio");
    p.match.rmse_m = m.at("rmse_m");
    p.match.T_map_robot = p.T_map_robot;
    poses.push_back(p);
  }
  return poses;
}

}  // namespace olt
