#include "olt/propagate/label_map.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "olt/core/error.h"

namespace olt {

uint16_t LabelMap::class_id(const std::string& name) const {
  for (const auto& c : classes)
    if (c.name == name) return c.id;
  throw std::out_of_range("no class " + name);
}

uint16_t LabelMap::instance_id(const std::string& name) const {
  for (const auto& i : instances)
    if (i.name == name) return i.id;
  throw std::out_of_range("no instance " + name);
}

const LabelClass* LabelMap::find_class(uint16_t id) const {
  for (const auto& c : classes)
    if (c.id == id) return &c;
  return nullptr;
}

std::array<uint8_t, 3> class_color(uint16_t id) {
  // Hues spread by the golden angle; saturation and value alternate so neighbours differ.
  const double hue = std::fmod(id * 137.508, 360.0);
  const double s = (id % 2) ? 0.85 : 0.6, v = (id % 3) ? 0.95 : 0.75;
  const double c = v * s, x = c * (1 - std::abs(std::fmod(hue / 60.0, 2.0) - 1)), m = v - c;
  double r = 0, g = 0, b = 0;
  if (hue < 60)
    r = c, g = x;
  else if (hue < 120)
    r = x, g = c;
  else if (hue < 180)
    g = c, b = x;
  else if (hue < 240)
    g = x, b = c;
  else if (hue < 300)
    r = x, b = c;
  else
    r = c, b = x;
  auto byte = [&](double value) { return static_cast<uint8_t>(std::lround(255 * (value + m))); };
  return {byte(r), byte(g), byte(b)};
}

LabelMap make_label_map(const std::vector<Box>& boxes, const std::map<std::string, int>& fixed) {
  LabelMap map;
  std::set<std::string> names;
  for (const auto& b : boxes) names.insert(b.label);
  std::set<int> used;
  for (const auto& [name, id] : fixed) {
    if (!used.insert(id).second) throw InputError("class_ids", "id " + std::to_string(id) + " is given to two classes");
    names.insert(name);
  }
  int next = 1;
  for (const auto& name : names) {
    int id;
    if (auto it = fixed.find(name); it != fixed.end()) {
      id = it->second;
    } else {
      while (used.count(next)) ++next;
      id = next;
      used.insert(id);
    }
    map.classes.push_back({static_cast<uint16_t>(id), name, class_color(static_cast<uint16_t>(id))});
  }
  std::sort(map.classes.begin(), map.classes.end(), [](const auto& a, const auto& b) { return a.id < b.id; });

  std::map<std::string, std::string> instance_class;
  for (const auto& b : boxes) {
    auto [it, inserted] = instance_class.emplace(b.instance, b.label);
    if (!inserted && it->second != b.label)
      throw InputError("annotations", "instance '" + b.instance + "' has boxes of two classes ('" + it->second +
                                          "' and '" + b.label + "')");
  }
  uint16_t id = 1;
  for (const auto& [name, label] : instance_class) map.instances.push_back({id++, name, map.class_id(label)});
  return map;
}

nlohmann::json to_json(const LabelMap& map) {
  nlohmann::json classes = nlohmann::json::array(), instances = nlohmann::json::array();
  for (const auto& c : map.classes) classes.push_back({{"id", c.id}, {"name", c.name}, {"color", c.color}});
  for (const auto& i : map.instances) instances.push_back({{"id", i.id}, {"name", i.name}, {"class_id", i.class_id}});
  return {{"classes", classes}, {"instances", instances}, {"unlabeled", kUnlabeled}, {"no_depth", kNoDepth}};
}

LabelMap label_map_from_json(const nlohmann::json& j) {
  LabelMap map;
  for (const auto& c : j.at("classes")) map.classes.push_back({c.at("id"), c.at("name"), c.at("color")});
  for (const auto& i : j.at("instances")) map.instances.push_back({i.at("id"), i.at("name"), i.at("class_id")});
  return map;
}

}  // namespace olt
