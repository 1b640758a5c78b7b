#pragma once
// The propagate stage's look at the boxes as a whole, from the frame records: per box and per
// instance the pixels labeled and the frames that see and label it, and warnings for boxes that are
// likely wrong (seen by no frame, labeling nothing, in the wrong units, swallowing the surface
// they stand on).
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
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

/// What the checks (and the stage's totals) read of one frame record: the frame's pixel counts and
/// each box's, a few bytes per box where the record's JSON takes kilobytes (10,000 frames are held).
struct FrameCounts {
  struct Box {
    uint32_t box = 0;  ///< its position in the boxes the counts are taken with (not its names: 10,000 frames' are kept)
    int64_t labeled_pixels = 0, bottom_pixels = 0;
  };
  int64_t labeled_pixels = 0, depth_pixels = 0, ambiguous_pixels = 0;
  std::vector<Box> boxes;
};

/// Each box id's position in a list of boxes.
std::map<std::string, uint32_t> box_positions(const std::vector<Box>& boxes);

/// The counts of a frame record (propagate's frame.json), from its text: only the members counted are
/// kept as JSON while it is parsed (a record is mostly rectangles; 10,000 are read after every edit).
/// Its boxes by their position in `positions`; a box the record names that is not there is left out.
FrameCounts frame_counts(const std::string& record, const std::map<std::string, uint32_t>& positions);

/// `frames`: the counts of the labeled observations (empty where none), taken with `boxes`; `cameras`: where each
/// camera was (the labeled observations' positions); `max_depth_m`: the farthest depth read.
BoxChecks check_boxes(const std::vector<Box>& boxes, const std::vector<std::optional<FrameCounts>>& frames,
                      const std::vector<Eigen::Vector3d>& cameras, double max_depth_m);

}  // namespace olt
