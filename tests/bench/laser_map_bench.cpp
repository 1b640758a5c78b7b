// Laser map benchmark: builds the map of a scan log and compares the robot poses at the reference
// keyframes' scans with the keyframe poses after a least-squares 2D alignment. Other trajectories
// (TUM files, e.g. MRPT icp-slam's path, and odometry) are judged the same way.
//   olt_bench_laser_map SCANS ODOMETRY KEYFRAMES KEYFRAME_SCANS [NAME=TUM_FILE[@SECONDS]]...
// Prints one JSON line per trajectory: translation / heading RMSE and max, seconds (median of 5).
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "olt/core/fs.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/laser/laser_map.h"
#include "olt/model/trajectory.h"

using namespace olt;

namespace {

struct Reference {
  std::vector<double> times;
  std::vector<Pose2> poses;
};

Reference read_reference(const std::string& keyframes_file, const std::string& scans_file) {
  const std::vector<LaserScan> scans = parse_laser_scans(scans_file, read_file(scans_file));
  std::map<int, double> time_of;
  for (const auto& s : scans) time_of[s.index] = s.timestamp;
  Reference r;
  std::istringstream in(read_file(keyframes_file));
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    int kf;
    double x, y, z, yaw;
    words >> kf >> x >> y >> z >> yaw;
    r.times.push_back(time_of.at(kf));
    r.poses.push_back(pose2(x, y, yaw));
  }
  return r;
}

// Least-squares rigid 2D alignment of `estimate` onto `reference` (Umeyama without scale), then
// translation and heading errors.
nlohmann::json judge(const std::vector<Pose2>& estimate, const std::vector<Pose2>& reference) {
  Eigen::Vector2d me = Eigen::Vector2d::Zero(), mr = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < estimate.size(); ++i) {
    me += estimate[i].translation();
    mr += reference[i].translation();
  }
  me /= estimate.size();
  mr /= estimate.size();
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Eigen::Vector2d a = estimate[i].translation() - me, b = reference[i].translation() - mr;
    sxx += a.dot(b);
    sxy += a.x() * b.y() - a.y() * b.x();
  }
  const double angle = std::atan2(sxy, sxx);
  const Pose2 align = pose2(0, 0, angle);
  const Eigen::Vector2d shift = mr - align.linear() * me;
  double t2 = 0, h2 = 0, t_max = 0, h_max = 0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Eigen::Vector2d p = align.linear() * estimate[i].translation() + shift;
    const double dt = (p - reference[i].translation()).norm();
    const double dh = std::abs(std::remainder(heading(estimate[i]) + angle - heading(reference[i]), 2 * M_PI)) * 180 / M_PI;
    t2 += dt * dt;
    h2 += dh * dh;
    t_max = std::max(t_max, dt);
    if (std::getenv("OLT_LASER_DUMP")) std::fprintf(stderr, "%zu %.3f %.2f\n", i, dt, dh);
    h_max = std::max(h_max, dh);
  }
  const double n = static_cast<double>(estimate.size());
  return {{"poses", estimate.size()}, {"translation_rmse_m", std::sqrt(t2 / n)}, {"translation_max_m", t_max},
          {"heading_rmse_deg", std::sqrt(h2 / n)}, {"heading_max_deg", h_max}};
}

std::vector<Pose2> at_times(const std::vector<double>& times, const std::vector<double>& reference_times,
                            const std::vector<Pose2>& poses) {
  std::vector<Pose2> out;
  for (double t : reference_times) {
    const auto it = std::min_element(times.begin(), times.end(),
                                     [t](double a, double b) { return std::abs(a - t) < std::abs(b - t); });
    out.push_back(poses[it - times.begin()]);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: olt_bench_laser_map SCANS ODOMETRY KEYFRAMES KEYFRAME_SCANS [NAME=TUM_FILE[@SECONDS]]...\n";
    return 2;
  }
  const std::vector<LaserScan> scans = parse_laser_scans(argv[1], read_file(argv[1]));
  const std::vector<OdometrySample> odometry = parse_odometry(argv[2], read_file(argv[2]));
  const Reference reference = read_reference(argv[3], argv[4]);

  // Settings from the environment (OLT_LASER_<NAME>=value), for exploring them.
  LaserMapSettings settings;
  const std::pair<const char*, double*> knobs[] = {
      {"KEY_DISTANCE_M", &settings.key_distance_m}, {"KEY_ANGLE_DEG", &settings.key_angle_deg},
      {"MAP_CELL_M", &settings.map_cell_m},         {"MAX_RANGE_M", &settings.max_range_m},
      {"HUBER_M", &settings.matching.huber_m},      {"MAX_CORRESPONDENCE_M", &settings.matching.max_correspondence_m},
      {"MIN_CORRESPONDENCE_M", &settings.matching.min_correspondence_m}, {"LOOP_RADIUS_M", &settings.loop_radius_m}};
  if (const char* v = std::getenv("OLT_LASER_LOCAL_KEYFRAMES")) settings.local_keyframes = std::stoi(v);
  for (const auto& [name, value] : knobs)
    if (const char* v = std::getenv((std::string("OLT_LASER_") + name).c_str())) *value = std::stod(v);
  std::vector<double> seconds;
  LaserMap result;
  for (int run = 0; run < 5; ++run) {
    const auto start = std::chrono::steady_clock::now();
    result = build_laser_map(scans, odometry, settings);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  std::vector<double> times;
  std::vector<Pose2> poses, odometry_poses;
  int keys = 0, flagged = 0;
  for (const auto& p : result.poses) {
    times.push_back(p.timestamp);
    poses.push_back(p.T_map_robot);
    odometry_poses.push_back(odometry_at(odometry, p.timestamp));
    keys += p.key;
    flagged += !p.valid;
  }
  nlohmann::json ours = judge(at_times(times, reference.times, poses), reference.poses);
  ours["name"] = "olt_laser_map";
  ours["seconds"] = seconds[2];
  ours["scans"] = scans.size();
  ours["keyframes"] = keys;
  ours["flagged"] = flagged;
  ours["map_points"] = result.map.size();
  ours["loop_closures"] = result.loop_closures;
  std::cout << ours.dump() << "\n";
  nlohmann::json odo = judge(at_times(times, reference.times, odometry_poses), reference.poses);
  odo["name"] = "raw_odometry";
  std::cout << odo.dump() << "\n";

  for (int i = 5; i < argc; ++i) {
    std::string arg = argv[i];
    const auto eq = arg.find('=');
    const auto at = arg.find('@');
    const std::string name = arg.substr(0, eq);
    const std::string file = arg.substr(eq + 1, at == std::string::npos ? std::string::npos : at - eq - 1);
    const Trajectory t = parse_tum_trajectory(file, read_file(file));
    std::vector<double> peer_times;
    std::vector<Pose2> peer_poses;
    for (const auto& s : t) {
      peer_times.push_back(s.timestamp);
      peer_poses.push_back(to_pose2(s.pose));
    }
    nlohmann::json row = judge(at_times(peer_times, reference.times, peer_poses), reference.poses);
    row["name"] = name;
    if (at != std::string::npos) row["seconds"] = std::stod(arg.substr(at + 1));
    std::cout << row.dump() << "\n";
  }
  return 0;
}
