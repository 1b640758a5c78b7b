#include "box_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "olt/propagate/propagate.h"

namespace olt {
namespace {

struct Tally {
  int64_t pixels = 0, bottom_pixels = 0;
  int frames_labeled = 0, frames_seeing = 0;
};

std::string metres(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), v >= 100 ? "%.0f m" : "%.2f m", v);
  return text;
}

std::string point(const Eigen::Vector3d& p) {
  char text[96];
  std::snprintf(text, sizeof(text), "(%.3g, %.3g, %.3g)", p.x(), p.y(), p.z());
  return text;
}

// A box a person would doubt: numbers in millimetres or centimetres put it far beyond what any
// camera sees, or make it larger than that space.
std::string units_warning(const Box& b, const std::vector<Eigen::Vector3d>& cameras, double max_depth_m) {
  if (cameras.empty()) return "";
  double nearest = INFINITY;
  for (const auto& c : cameras) nearest = std::min(nearest, (b.T_world_box.translation() - c).norm());
  const double largest = b.size.maxCoeff();
  const std::string hint = ": are its numbers in millimetres or centimetres? OLT reads metres";
  if (nearest > 2 * max_depth_m)
    return "box '" + b.id + "': its centre " + point(b.T_world_box.translation()) + " lies " + metres(nearest) +
           " from the nearest camera, beyond twice the depth range (" + metres(max_depth_m) + ")" + hint;
  if (largest > 2 * max_depth_m)
    return "box '" + b.id + "': " + metres(largest) + " long, more than twice the depth range (" + metres(max_depth_m) +
           ")" + hint;
  return "";
}

}  // namespace

std::map<std::string, uint32_t> box_positions(const std::vector<Box>& boxes) {
  std::map<std::string, uint32_t> positions;
  for (size_t k = 0; k < boxes.size(); ++k) positions.emplace(boxes[k].id, static_cast<uint32_t>(k));
  return positions;
}

FrameCounts frame_counts(const std::string& text, const std::map<std::string, uint32_t>& positions) {
  const nlohmann::json record =
      nlohmann::json::parse(text, [](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        if (event != nlohmann::json::parse_event_t::key) return true;
        const std::string& key = parsed.get_ref<const std::string&>();
        if (depth == 1)
          return key == "labeled_pixels" || key == "valid_pixels" || key == "ambiguous_pixels" || key == "boxes";
        return depth != 3 || key == "box" || key == "labeled_pixels" || key == "bottom_pixels";
      });
  FrameCounts counts{record["labeled_pixels"].get<int64_t>(),
                     record["valid_pixels"].get<int64_t>(),
                     record["ambiguous_pixels"].get<int64_t>(),
                     {}};
  counts.boxes.reserve(record["boxes"].size());  // of its size: 10,000 frames' lists are kept
  for (const auto& b : record["boxes"]) {
    const auto at = positions.find(b["box"].get<std::string>());
    if (at != positions.end())
      counts.boxes.push_back({at->second, b["labeled_pixels"].get<int64_t>(), b.value("bottom_pixels", int64_t{0})});
  }
  return counts;
}

BoxChecks check_boxes(const std::vector<Box>& boxes, const std::vector<std::optional<FrameCounts>>& frames,
                      const std::vector<Eigen::Vector3d>& cameras, double max_depth_m) {
  std::vector<Tally> by_box(boxes.size());
  std::map<std::string, std::pair<int64_t, int>> by_instance;  // pixels, frames labeled
  for (const auto& frame : frames) {
    if (!frame) continue;
    std::map<std::string, int64_t> instance_pixels;
    for (const auto& b : frame->boxes) {
      if (b.box >= boxes.size()) continue;
      Tally& t = by_box[b.box];
      t.pixels += b.labeled_pixels;
      t.bottom_pixels += b.bottom_pixels;
      t.frames_seeing += 1;
      t.frames_labeled += b.labeled_pixels > 0;
      instance_pixels[boxes[b.box].instance] += b.labeled_pixels;
    }
    for (const auto& [instance, pixels] : instance_pixels) {
      by_instance[instance].first += pixels;
      by_instance[instance].second += pixels > 0;
    }
  }
  BoxChecks checks{nlohmann::json::object(), nlohmann::json::object(), {}};
  for (size_t k = 0; k < boxes.size(); ++k) {
    const Box& b = boxes[k];
    const Tally t = by_box[k];
    checks.boxes[b.id] = {{"instance", b.instance},
                          {"label", b.label},
                          {"pixels", t.pixels},
                          {"frames_labeled", t.frames_labeled},
                          {"frames_seeing", t.frames_seeing}};
    auto& instance = checks.instances[b.instance];
    if (instance.is_null()) {
      const auto it = by_instance.find(b.instance);
      instance = {{"label", b.label},
                  {"boxes", nlohmann::json::array()},
                  {"pixels", it == by_instance.end() ? 0 : it->second.first},
                  {"frames", it == by_instance.end() ? 0 : it->second.second}};
    }
    instance["boxes"].push_back(b.id);
    const std::string units = units_warning(b, cameras, max_depth_m);
    if (!units.empty()) {
      checks.warnings.push_back(units);
    } else if (t.frames_seeing == 0) {
      checks.warnings.push_back("box '" + b.id + "' (" + b.label + "): no frame sees it; its centre " +
                                point(b.T_world_box.translation()) + " is outside every camera's view");
    } else if (t.pixels == 0) {
      checks.warnings.push_back("box '" + b.id + "' (" + b.label + "): " + std::to_string(t.frames_seeing) +
                                " frames see it but it labels no pixel: nothing with depth lies inside it "
                                "(floating above its object, or misplaced?)");
    } else if (t.bottom_pixels * 2 > t.pixels && t.pixels >= 100 && b.size.z() >= 5 * kBottomBand) {
      // (A box under 10 cm tall, a book or a mouse, has most of itself in the band.)
      checks.warnings.push_back("box '" + b.id + "' (" + b.label +
                                "): " + std::to_string(100 * t.bottom_pixels / t.pixels) +
                                "% of its pixels lie within 2 cm of its bottom face: it may hold the floor or table "
                                "it stands on; raise its bottom or give it a margin (\"margin\": 0.02)");
    }
  }
  return checks;
}

}  // namespace olt
