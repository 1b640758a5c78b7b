#pragma once
// The `laser_map` stage: the 2D map of the recording's laser scans (paper Sec. III-B), with the
// robot's pose at every scan, and a picture of it.
#include <string>

#include "olt/laser/laser_map.h"
#include "olt/stages/laser.h"

namespace olt {

struct LaserMapConfig {
  LaserMapSettings settings;         ///< every setting and its default lives there
  double image_resolution_m = 0.05;  ///< metres per pixel of map.png
  int image_max_px = 2000;           ///< longer side of map.png at most, pixels
};

struct LaserMapResult {
  LaserMap map;
  std::string picture_png;  ///< the map from above with the robot's path
};

LaserMapResult run_laser_map(const LaserData& in, const LaserMapConfig& c);

}  // namespace olt
