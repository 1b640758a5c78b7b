#pragma once
// A picture of a laser map for people: the map's points in black on white, the robot's path in
// blue (red where a scan failed to match), keyframes as dots, a 1 m scale bar; x to the right,
// y up.
#include <string>
#include <vector>

#include "olt/laser/laser_map.h"

namespace olt {

/// PNG bytes; `resolution_m` metres per pixel, the longer side at most `max_size_px`.
std::string render_map_png(const std::vector<Eigen::Vector2d>& points, const std::vector<ScanPose>& poses,
                           double resolution_m, int max_size_px);

}  // namespace olt
