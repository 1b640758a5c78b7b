#include "olt/formats/laser_text.h"

#include <cmath>
#include <cstdio>

#include "olt/core/error.h"
#include "olt/core/text.h"
#include "text_lines.h"

namespace olt {
namespace {

void check_increasing(const std::string& file, int line, double t, double previous, int previous_line, bool first) {
  if (!first && t <= previous)
    throw InputError({{file, line, 1,
                       "timestamp " + std::to_string(t) + " does not increase (previous line " +
                           std::to_string(previous_line) + ")"}});
}

}  // namespace

std::vector<LaserScan> parse_laser_scans(const std::string& file, const std::string& text) {
  std::vector<LaserScan> scans;
  int previous_line = 0;
  for_each_line(text, [&](int line, const std::vector<std::string>& f) {
    constexpr size_t kHead = 10;
    if (f.size() < kHead)
      throw InputError({{file, line, 1,
                         "expected 'idx timestamp sensor_x sensor_y sensor_z sensor_yaw aperture_rad right_to_left "
                         "max_range N ranges[N] valid[N]', got " +
                             std::to_string(f.size()) + " fields"}});
    const double n = parse_number(file, line, f[9], "N, the number of rays");
    if (n < 1 || n > 100000 || n != static_cast<int>(n))
      throw InputError({{file, line, 1, "N (rays) must be an integer in 1..100000, got '" + f[9] + "'"}});
    const size_t rays = static_cast<size_t>(n);
    if (f.size() != kHead + 2 * rays)
      throw InputError({{file, line, 1,
                         "N = " + f[9] + " rays needs " + std::to_string(kHead + 2 * rays) + " fields, got " +
                             std::to_string(f.size())}});
    LaserScan s;
    const double index = parse_number(file, line, f[0], "idx");
    if (index < 0 || index > 1e9 || index != std::floor(index))
      throw InputError({{file, line, 1, "idx must be an integer in 0..1e9, got '" + f[0] + "'"}});
    s.index = static_cast<int>(index);
    s.timestamp = parse_number(file, line, f[1], "the timestamp");
    check_increasing(file, line, s.timestamp, scans.empty() ? 0 : scans.back().timestamp, previous_line, scans.empty());
    const double x = parse_number(file, line, f[2], "sensor_x"), y = parse_number(file, line, f[3], "sensor_y"),
                 z = parse_number(file, line, f[4], "sensor_z"), yaw = parse_number(file, line, f[5], "sensor_yaw");
    s.T_robot_laser = to_pose3(pose2(x, y, yaw));
    s.T_robot_laser.translation().z() = z;
    s.aperture_rad = parse_number(file, line, f[6], "aperture_rad");
    if (s.aperture_rad <= 0 || s.aperture_rad > 2 * M_PI + 1e-6)
      throw InputError({{file, line, 1, "aperture_rad must be in (0, 2 pi], got '" + f[6] + "'"}});
    const double rtl = parse_number(file, line, f[7], "right_to_left");
    if (rtl != 0 && rtl != 1) throw InputError({{file, line, 1, "right_to_left must be 0 or 1, got '" + f[7] + "'"}});
    s.right_to_left = rtl == 1;
    s.max_range_m = parse_number(file, line, f[8], "max_range");
    if (s.max_range_m <= 0) throw InputError({{file, line, 1, "max_range must be positive, got '" + f[8] + "'"}});
    s.ranges.resize(rays);
    s.valid.resize(rays);
    for (size_t k = 0; k < rays; ++k) {
      s.ranges[k] = static_cast<float>(parse_number(file, line, f[kHead + k], "range " + std::to_string(k)));
      const std::string& v = f[kHead + rays + k];
      if (v != "0" && v != "1")
        throw InputError({{file, line, 1, "valid[" + std::to_string(k) + "] must be 0 or 1, got '" + v + "'"}});
      s.valid[k] = v == "1";
    }
    scans.push_back(std::move(s));
    previous_line = line;
  });
  return scans;
}

std::string check_scan(LaserScan& scan) {
  if (scan.ranges.empty() || scan.ranges.size() > 100000) return "a scan must have 1 to 100000 rays";
  if (!(scan.aperture_rad > 0 && scan.aperture_rad <= 2 * M_PI + 1e-6)) return "a scan's aperture must be in (0, 2 pi]";
  if (!(scan.max_range_m >= 0.001 && scan.max_range_m < 1e6)) return "a scan's maximum range must be 1 mm to 1000 km";
  if (!scan.T_robot_laser.matrix().allFinite()) return "a scan's sensor pose is not finite";
  // The text formats keep the scanner's x, y, z and yaw: a level scanner. One mounted upside down
  // (rolled half a turn) is a level one scanning the other way round; one tilted is refused.
  const double up = scan.T_robot_laser.linear()(2, 2);
  if (up < -0.99) {
    const Pose2 level = to_pose2(scan.T_robot_laser);
    const double z = scan.T_robot_laser.translation().z();
    scan.T_robot_laser = to_pose3(level);
    scan.T_robot_laser.translation().z() = z;
    scan.right_to_left = !scan.right_to_left;
  } else if (up < 0.99) {
    return "a scan's sensor is tilted " + std::to_string(std::acos(std::min(1.0, std::abs(up))) * 180 / M_PI) +
           " degrees from level; a 2D laser map needs a level scanner";
  }
  scan.valid.resize(scan.ranges.size(), 1);
  for (size_t k = 0; k < scan.ranges.size(); ++k)
    if (!std::isfinite(scan.ranges[k]) || std::abs(scan.ranges[k]) > 1e6) {
      scan.ranges[k] = static_cast<float>(scan.max_range_m);
      scan.valid[k] = 0;
    }
  return "";
}

std::string format_laser_scans(const std::vector<LaserScan>& scans) {
  std::string text =
      "# idx timestamp sensor_x sensor_y sensor_z sensor_yaw aperture_rad right_to_left max_range N ranges[N] "
      "valid[N]\n";
  for (const auto& s : scans) {
    const Pose2 p = to_pose2(s.T_robot_laser);
    text += format_text("%d %.9f %.6f %.6f %.6f %.9f %.9f %d %.3f %zu", s.index, s.timestamp, p.translation().x(),
                        p.translation().y(), s.T_robot_laser.translation().z(), heading(p), s.aperture_rad,
                        s.right_to_left ? 1 : 0, s.max_range_m, s.ranges.size());
    char buffer[64];  // " %.4f" of any float: at most 46 characters
    for (float r : s.ranges) {
      std::snprintf(buffer, sizeof(buffer), " %.4f", r);
      text += buffer;
    }
    for (size_t k = 0; k < s.ranges.size(); ++k) text += k < s.valid.size() && !s.valid[k] ? " 0" : " 1";
    text += '\n';
  }
  return text;
}

std::vector<OdometrySample> parse_odometry(const std::string& file, const std::string& text) {
  std::vector<OdometrySample> odometry;
  int previous_line = 0;
  for_each_line(text, [&](int line, const std::vector<std::string>& f) {
    if (f.size() != 5)
      throw InputError(
          {{file, line, 1, "expected 'idx timestamp x y theta', got " + std::to_string(f.size()) + " fields"}});
    OdometrySample s;
    parse_number(file, line, f[0], "idx");
    s.timestamp = parse_number(file, line, f[1], "the timestamp");
    check_increasing(file, line, s.timestamp, odometry.empty() ? 0 : odometry.back().timestamp, previous_line,
                     odometry.empty());
    s.pose = pose2(parse_number(file, line, f[2], "x"), parse_number(file, line, f[3], "y"),
                   parse_number(file, line, f[4], "theta"));
    odometry.push_back(s);
    previous_line = line;
  });
  return odometry;
}

std::string format_odometry(const std::vector<OdometrySample>& odometry) {
  std::string text = "# idx timestamp x y theta\n";
  for (size_t i = 0; i < odometry.size(); ++i) {
    const auto& s = odometry[i];
    text += format_text("%zu %.6f %.6f %.6f %.9f\n", i, s.timestamp, s.pose.translation().x(), s.pose.translation().y(),
                        heading(s.pose));
  }
  return text;
}

PointMapText parse_point_map(const std::string& file, const std::string& text) {
  PointMapText map;
  for_each_line(text, [&](int line, const std::vector<std::string>& f) {
    if (f.size() != 4)
      throw InputError({{file, line, 1, "expected 'x y nx ny', got " + std::to_string(f.size()) + " fields"}});
    map.points.emplace_back(parse_number(file, line, f[0], "x"), parse_number(file, line, f[1], "y"));
    const Eigen::Vector2d n(parse_number(file, line, f[2], "nx"), parse_number(file, line, f[3], "ny"));
    if (n.squaredNorm() != 0 && std::abs(n.norm() - 1) > 0.01)
      throw InputError({{file, line, 1, "the normal must be a unit vector or 0 0"}});
    map.normals.push_back(n);
  });
  if (map.points.empty()) throw InputError(file, "holds no map points");
  return map;
}

std::string format_point_map(const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& normals) {
  std::string text = "# x y nx ny (map frame, metres; normal 0 0 where the map is not locally straight)\n";
  for (size_t i = 0; i < points.size(); ++i)
    text += format_text("%.4f %.4f %.4f %.4f\n", points[i].x(), points[i].y(), normals[i].x(), normals[i].y());
  return text;
}

}  // namespace olt
