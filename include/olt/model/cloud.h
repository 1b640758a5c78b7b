#pragma once
#include <cstdint>
#include <vector>

namespace olt {

struct ColoredPoint {
  float x = 0, y = 0, z = 0;  ///< metres
  uint8_t r = 0, g = 0, b = 0;
};

using ColoredCloud = std::vector<ColoredPoint>;

/// A depth point with its colour and labels (class and instance ids as in the label images).
struct LabeledPoint {
  float x = 0, y = 0, z = 0;  ///< metres
  uint8_t r = 0, g = 0, b = 0;
  uint16_t class_id = 0, instance_id = 0;
};

using LabeledCloud = std::vector<LabeledPoint>;

}  // namespace olt
