#pragma once
// Plain-text laser scans and odometry (the layout of ../shared/data/mrpt_laser/text, converted from
// MRPT rawlogs; also what OLT writes for the recordings it reads or generates):
//   scans:    idx timestamp sensor_x sensor_y sensor_z sensor_yaw aperture_rad right_to_left
//             max_range N ranges[N] valid[N]   (one scan per line; ray k at -aperture/2 + k *
//             aperture/(N-1), mirrored when right_to_left is 0)
//   odometry: idx timestamp x y theta          (integrated from the start; radians)
//   map:      x y nx ny                       (a 2D point map with unit normals, 0 0 where none)
// '#' starts a comment line; timestamps in seconds, strictly increasing.
#include <string>
#include <vector>

#include "olt/model/laser.h"

namespace olt {

/// Throws InputError naming file:line on a malformed line (field count, non-finite number, N out of
/// 1..100000, validity not 0/1, a timestamp that does not increase).
std::vector<LaserScan> parse_laser_scans(const std::string& file, const std::string& text);
std::string format_laser_scans(const std::vector<LaserScan>& scans);

/// What is wrong with a scan read from elsewhere (a rawlog, the plain-text layout): "" when it can
/// be written and read back; non-finite ranges are marked invalid on the way.
std::string check_scan(LaserScan& scan);

std::vector<OdometrySample> parse_odometry(const std::string& file, const std::string& text);
std::string format_odometry(const std::vector<OdometrySample>& odometry);

/// A laser map's points and normals (map frame).
struct PointMapText {
  std::vector<Eigen::Vector2d> points, normals;
};
PointMapText parse_point_map(const std::string& file, const std::string& text);
std::string format_point_map(const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& normals);

}  // namespace olt
