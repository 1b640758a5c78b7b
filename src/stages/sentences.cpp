// One plain sentence per stage kind, from its summary: what a person wants to read in a log.
#include "olt/stages/sentences.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

namespace olt {
namespace {

using Json = nlohmann::json;

int64_t count(const Json& s, const char* key) {
  const auto it = s.find(key);
  if (it == s.end()) return 0;
  if (it->is_array() || it->is_object()) return static_cast<int64_t>(it->size());
  return it->is_number() ? it->get<int64_t>() : 0;
}

// "3 observations", "1 observation", "2 boxes"
std::string things(int64_t n, const std::string& noun) {
  if (n == 1) return "1 " + noun;
  const char last = noun.empty() ? ' ' : noun.back();
  return std::to_string(n) + " " + noun + (last == 's' || last == 'x' ? "es" : "s");
}

std::string fixed(double value, int digits) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

// "; 2 of 100 observations (2%) flagged" when any is
std::string flagged(const Json& s, int64_t total, const std::string& noun) {
  const int64_t n = count(s, "flagged");
  if (n == 0) return "";
  return "; " + std::to_string(n) + " of " + things(total, noun) + " (" + percent(n, total) + ") flagged and left out";
}

std::string source(const Json& s) {
  std::string text = "read " + things(count(s, "observations"), "RGB-D observation");
  if (count(s, "without_color")) text += " (" + std::to_string(count(s, "without_color")) + " without colour)";
  if (count(s, "laser_scans")) text += ", " + things(count(s, "laser_scans"), "laser scan");
  if (count(s, "other_laser_scans"))
    text += " (and " + std::to_string(count(s, "other_laser_scans")) + " of other lasers, not used)";
  if (count(s, "odometry_samples")) text += ", " + things(count(s, "odometry_samples"), "odometry sample");
  if (count(s, "dropped_out_of_order"))
    text += "; dropped " + std::to_string(count(s, "dropped_out_of_order")) + " records out of time order";
  return text;
}

std::string laser_map(const Json& s) {
  return "mapped " + things(count(s, "scans"), "scan") + " along a " + fixed(s.value("path_length_m", 0.0), 1) +
         " m path: " + things(count(s, "keyframes"), "keyframe") + ", " +
         things(count(s, "loop_closures"), "loop closure") + ", " + things(count(s, "map_points"), "map point") +
         flagged(s, count(s, "scans"), "scan");
}

std::string poses(const Json& s) {
  const int64_t total = count(s, "observations");
  std::string text = "posed " + things(total - count(s, "flagged"), "observation");
  if (s.contains("keyframes"))
    text += " by registration (" + things(count(s, "keyframes"), "keyframe") + ", " +
            things(count(s, "loop_closures"), "loop closure") +
            (count(s, "loop_closures_refused") ? ", " + std::to_string(count(s, "loop_closures_refused")) + " refused"
                                               : "") +
            ")";
  if (s.contains("scans"))
    text += " from " + things(count(s, "scans"), "localized laser scan") +
            (count(s, "scans_failed") ? " (" + std::to_string(count(s, "scans_failed")) + " failed)" : "");
  const int64_t outside = count(s, "observations_outside_scans") + count(s, "observations_in_scan_gaps") +
                          count(s, "observations_next_to_failed_scans");
  if (outside) text += "; " + things(outside, "observation") + " outside the scans, in gaps or next to failed scans";
  if (count(s, "inconsistent"))
    text += "; " + things(count(s, "inconsistent"), "observation") + " inconsistent with the scene";
  return text + flagged(s, total, "observation");
}

std::string propagate(const Json& s) {
  const int64_t labeled = count(s, "observations_labeled"), skipped = count(s, "observations_skipped");
  std::string text = "labeled " + things(labeled, "observation");
  const int64_t in_place = count(s, "frames_in_place");
  const std::string only_changed = std::to_string(in_place) + " of them only where boxes changed";
  if (s.contains("frames_reused") && count(s, "frames_reused"))
    text += " (" + std::to_string(count(s, "frames_labeled")) + " relabeled" +
            (in_place ? ", " + only_changed + ";" : ",") + " " + std::to_string(count(s, "frames_reused")) +
            " unchanged)";
  else if (in_place)
    text += " (" + only_changed + ")";
  if (skipped) text += ", skipped " + std::to_string(skipped) + " (flagged poses)";
  if (s.contains("depth_pixels")) {
    const double depth = static_cast<double>(count(s, "depth_pixels"));
    text += "; " + percent(static_cast<double>(count(s, "labeled_pixels")), depth) +
            " of their depth pixels inside a box, " +
            percent(static_cast<double>(count(s, "ambiguous_pixels")), depth) + " inside more than one";
  }
  text += "; " + things(count(s, "classes"), "class") + ", " + things(count(s, "instances"), "instance") + " seen";
  return text;
}

std::string reconstruct(const Json& s) {
  std::string text =
      "fused " + things(count(s, "observations_fused"), "observation") + " into " + things(count(s, "points"), "point");
  const std::string by = s.value("levelled_by", "");
  if (by == "support_plane")
    text += "; levelled on the support plane (tilted " + fixed(s.value("tilt_deg", 0.0), 1) + "° from the poses' z)";
  else if (!by.empty() && by != "none")
    text += "; levelled by " + by + " (tilted " + fixed(s.value("tilt_deg", 0.0), 1) + "°)";
  return text;
}

const std::map<std::string, std::function<std::string(const Json&)>>& sentences() {
  static const std::map<std::string, std::function<std::string(const Json&)>> table{
      {"source", source},
      {"calibrate", [](const Json& s) { return "calibrated " + things(count(s, "sensors"), "sensor"); }},
      {"laser_map", laser_map},
      {"poses", poses},
      {"annotations", [](const Json& s) { return "read " + things(count(s, "boxes"), "box"); }},
      {"propagate", propagate},
      {"export",
       [](const Json& s) {
         return "exported " + things(count(s, "images"), "image") + " with " +
                things(count(s, "annotations"), "object annotation");
       }},
      {"reconstruct", reconstruct},
      {"report", [](const Json&) { return std::string("wrote the report page"); }},
  };
  return table;
}

}  // namespace

std::string percent(double part, double whole) {
  if (whole <= 0) return "0%";
  const double p = 100.0 * part / whole;
  if (!std::isfinite(p)) return "-";
  if (p > 0 && p < 0.1) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.2g%%", p);
    return text;
  }
  return fixed(p, std::floor(p) == p ? 0 : 1) + "%";
}

std::string stage_sentence(const std::string& kind, const nlohmann::json& summary) {
  // A shard's part of a stage with units: {"frames_labeled": 3, "frames_reused": 1}.
  if (summary.is_object() && summary.size() == 2) {
    std::string done, reused;
    for (const auto& [key, value] : summary.items())
      (key.size() > 7 && key.compare(key.size() - 7, 7, "_reused") == 0 ? reused : done) = key;
    if (!done.empty() && !reused.empty() && done.find('_') != std::string::npos) {
      const std::string units = done.substr(0, done.find('_'));
      return std::to_string(count(summary, done.c_str())) + " " + units + " " + done.substr(done.find('_') + 1) + ", " +
             std::to_string(count(summary, reused.c_str())) + " already in the cache";
    }
  }
  const auto it = sentences().find(kind);
  if (it == sentences().end() || !summary.is_object()) return summary.dump();
  std::string text = it->second(summary);
  if (const int64_t warnings = count(summary, "warnings"))
    text += "; " + things(warnings, "warning") + " (listed at the end)";
  return text;
}

}  // namespace olt
