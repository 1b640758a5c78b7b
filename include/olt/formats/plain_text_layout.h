#pragma once
// The OLT / Robot@Home plain-text layout (the original toolkit's CSaveAsPlainText):
//   <sequence>.txt   '#' header lines, then per observation:
//                    obs_id sensor_label x y z yaw pitch roll timestamp
//                    (the sensor's pose on the robot in metres and radians, MRPT's camera frame
//                    for RGB-D sensors: x forward, y left, z up; the timestamp in 100 ns ticks since
//                    1601-01-01 UTC, or UNIX seconds);
//   <folder>/<id>_scan.txt       a 2D scan: '#' lines, aperture (rad), max range (m), N, N ranges,
//                                N validity flags (1/0); rays from right to left;
//   <folder>/<id>_depth.png      16-bit depth, metres * 65535 / 10;
//   <folder>/<id>_intensity.png  the colour image.
#include <string>
#include <vector>

#include "olt/model/laser.h"

namespace olt {

struct PlainTextEntry {
  int line = 0;
  std::string id;
  std::string sensor;
  Pose sensor_pose = Pose::Identity();  ///< as written: x y z yaw pitch roll, MRPT frames
  double timestamp = 0;                 ///< UNIX seconds
};

constexpr double kPlainTextDepthScale = 65535.0 / 10.0;  ///< depth PNG units per metre

/// Throws InputError naming file:line on a malformed line.
std::vector<PlainTextEntry> parse_plain_text_sequence(const std::string& file, const std::string& text);

/// A `<id>_scan.txt` file as a scan taken at `entry`'s time from its sensor pose.
LaserScan parse_plain_text_scan(const std::string& file, const std::string& text, const PlainTextEntry& entry);

}  // namespace olt
