#pragma once
#include <cstdint>
#include <vector>

namespace olt {

struct ColoredPoint {
  float x = 0, y = 0, z = 0;  ///< metres
  uint8_t r = 0, g = 0, b = 0;
};

using ColoredCloud = std::vector<ColoredPoint>;

}  // namespace olt
