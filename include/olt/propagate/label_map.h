#pragma once
// The label map: class and instance ids of a dataset. Class ids are stable across runs and
// sequences: ids a job fixes (`class_ids`) are kept; other classes get the next free ids in
// alphabetical order of their names. Instance ids are 1..M in alphabetical order of instance names.
// 0 is "unlabeled" (a depth point in no box); 65535 is "no_depth" (no valid depth reading).
#include <array>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/core/box.h"

namespace olt {

constexpr uint16_t kUnlabeled = 0;
constexpr uint16_t kNoDepth = 65535;

struct LabelClass {
  uint16_t id = 0;
  std::string name;
  std::array<uint8_t, 3> color{};  ///< r, g, b
};

struct LabelInstance {
  uint16_t id = 0;
  std::string name;
  uint16_t class_id = 0;
};

struct LabelMap {
  std::vector<LabelClass> classes;       ///< sorted by id
  std::vector<LabelInstance> instances;  ///< sorted by id

  uint16_t class_id(const std::string& name) const;
  uint16_t instance_id(const std::string& name) const;
  const LabelClass* find_class(uint16_t id) const;
};

/// Throws InputError when fixed ids collide or an instance spans two classes.
LabelMap make_label_map(const std::vector<Box>& boxes, const std::map<std::string, int>& fixed_class_ids);

/// A well-separated colour for class id `id` (deterministic).
std::array<uint8_t, 3> class_color(uint16_t id);

/// labels.json: {"classes":[{"id","name","color"}], "instances":[...], "unlabeled":0, "no_depth":65535}
nlohmann::json to_json(const LabelMap& map);
LabelMap label_map_from_json(const nlohmann::json& j);

}  // namespace olt
