#pragma once
// The propagate stage's look at the boxes as a whole, from the frame records: per box and per
// instance the pixels labeled and the frames that see and label it, and warnings for boxes that are
// likely wrong (seen by no frame, labeling nothing, in the wrong units, swallowing the surface
// they stand on).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/geometry.h"

namespace olt {

struct BoxChecks {
  nlohmann::json boxes;      ///< box id -> {instance, label, pixels, frames_labeled, frames_seeing}
  nlohmann::json instances;  ///< instance -> {label, boxes, pixels, frames}
  std::vector<std::string> warnings;
};

/// `records`: the frame records of the labeled observations (null where none); `cameras`: where
/// each camera was (the labeled observations' positions); `max_depth_m`: the farthest depth read.
BoxChecks check_boxes(const std::vector<Box>& boxes, const std::vector<nlohmann::json>& records,
                      const std::vector<Eigen::Vector3d>& cameras, double max_depth_m);

}  // namespace olt
