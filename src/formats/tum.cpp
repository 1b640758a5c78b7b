#include "olt/formats/tum.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "olt/core/error.h"
#include "olt/core/text.h"
#include "text_lines.h"

namespace olt {

std::vector<TumListEntry> parse_tum_list(const std::string& file, const std::string& text) {
  check_utf8(file, text);  // file names end up in JSON
  std::vector<TumListEntry> entries;
  for_each_line(text, [&](int line, const std::vector<std::string>& f) {
    if (f.size() != 2)
      throw InputError({{file, line, 1, "expected 'timestamp filename', got " + std::to_string(f.size()) + " fields"}});
    const double t = parse_number(file, line, f[0], "the timestamp");
    if (!entries.empty() && t <= entries.back().timestamp)
      throw InputError(
          {{file, line, 1,
            "timestamp " + f[0] + " does not increase (previous line " + std::to_string(entries.back().line) + ")"}});
    entries.push_back({t, f[0], f[1], line});
  });
  return entries;
}

std::vector<TrajectorySample> parse_tum_trajectory(const std::string& file, const std::string& text) {
  static const char* kNames[] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  std::vector<TrajectorySample> samples;
  int previous_line = 0;
  for_each_line(text, [&](int line, const std::vector<std::string>& f) {
    if (f.size() != 8)
      throw InputError(
          {{file, line, 1, "expected 'timestamp tx ty tz qx qy qz qw', got " + std::to_string(f.size()) + " fields"}});
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = parse_number(file, line, f[i], kNames[i]);
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 0.1)
      throw InputError({{file, line, 1, "quaternion norm " + std::to_string(q.norm()) + " is not close to 1"}});
    if (!samples.empty() && v[0] <= samples.back().timestamp)
      throw InputError(
          {{file, line, 1,
            "timestamp " + f[0] + " does not increase (previous line " + std::to_string(previous_line) + ")"}});
    samples.push_back({v[0], pose_from_tq(Eigen::Vector3d(v[1], v[2], v[3]), q)});
    previous_line = line;
  });
  return samples;
}

std::string format_tum_trajectory(const std::vector<TrajectorySample>& samples) {
  std::string text = "# timestamp tx ty tz qx qy qz qw\n";
  for (const auto& s : samples) {
    const auto p = pose_to_json(s.pose);
    text +=
        format_text("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", s.timestamp, p[0].get<double>(), p[1].get<double>(),
                    p[2].get<double>(), p[3].get<double>(), p[4].get<double>(), p[5].get<double>(), p[6].get<double>());
  }
  return text;
}

}  // namespace olt
