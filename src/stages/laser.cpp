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
