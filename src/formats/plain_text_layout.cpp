#include "olt/formats/plain_text_layout.h"

#include "olt/core/error.h"
#include "text_lines.h"

namespace olt {
namespace {

// MRPT timestamps count 100 ns ticks since 1601-01-01 UTC; 11644473600 s separate that from 1970.
double unix_seconds(double value) { return value > 1e15 ? value * 1e-7 - 11644473600.0 : value; }

}  // namespace

std::vector<PlainTextEntry> parse_plain_text_sequence(const std::string& file, const std::string& text) {
  check_utf8(file, text);  // ids and labels end up in JSON
  std::vector<PlainTextEntry> entries;
  for_each_line(text, [&](int line, const std::vector<std::string>& f) {
    if (f.size() != 9)
      throw InputError({{file, line, 1,
                         "expected 'obs_id sensor_label x y z yaw pitch roll timestamp', got " +
                             std::to_string(f.size()) + " fields"}});
    PlainTextEntry e;
    e.line = line;
    e.id = f[0];
    e.sensor = f[1];
    double v[6];
    static const char* kNames[] = {"x", "y", "z", "yaw", "pitch", "roll"};
    for (int k = 0; k < 6; ++k) v[k] = parse_number(file, line, f[2 + k], kNames[k]);
    e.sensor_pose = pose_from_xyz_ypr_deg({v[0], v[1], v[2], v[3] * 180 / M_PI, v[4] * 180 / M_PI, v[5] * 180 / M_PI});
    e.timestamp = unix_seconds(parse_number(file, line, f[8], "the timestamp"));
    entries.push_back(e);
  });
  return entries;
}

LaserScan parse_plain_text_scan(const std::string& file, const std::string& text, const PlainTextEntry& entry) {
  std::vector<std::string> words;
  std::vector<int> lines;
  for_each_line(text, [&](int line, const std::vector<std::string>& f) {
    for (const auto& w : f) {
      words.push_back(w);
      lines.push_back(line);
    }
  });
  auto number = [&](size_t k, const std::string& what) {
    if (k >= words.size()) throw InputError(file, "ends before " + what);
    return parse_number(file, lines[k], words[k], what);
  };
  LaserScan s;
  s.timestamp = entry.timestamp;
  s.T_robot_laser = entry.sensor_pose;
  s.right_to_left = true;
  s.aperture_rad = number(0, "the aperture");
  s.max_range_m = number(1, "the maximum range");
  const double n = number(2, "the number of rays");
  if (n < 1 || n > 100000 || n != static_cast<int>(n))
    throw InputError({{file, lines[2], 1, "the number of rays must be an integer in 1..100000"}});
  const size_t rays = static_cast<size_t>(n);
  if (words.size() != 3 + 2 * rays)
    throw InputError(file, std::to_string(rays) + " rays need " + std::to_string(rays) + " ranges and " +
                               std::to_string(rays) + " validity flags, found " + std::to_string(words.size() - 3) +
                               " values");
  for (size_t k = 0; k < rays; ++k) {
    s.ranges.push_back(static_cast<float>(number(3 + k, "range " + std::to_string(k))));
    const std::string& v = words[3 + rays + k];
    if (v != "0" && v != "1")
      throw InputError({{file, lines[3 + rays + k], 1, "validity flags are 0 or 1, got '" + v + "'"}});
    s.valid.push_back(v == "1");
  }
  return s;
}

}  // namespace olt
