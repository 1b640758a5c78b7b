#pragma once
// TUM RGB-D text formats (https://cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats):
//   list files (rgb.txt, depth.txt): "timestamp filename" per line, '#' comments;
//   trajectories: "timestamp tx ty tz qx qy qz qw" per line, '#' comments; the pose maps the
//   camera (or robot) frame into the world frame; timestamps in seconds, strictly increasing.
#include <string>
#include <vector>

#include "olt/core/fs.h"
#include "olt/model/trajectory.h"

namespace olt {

struct TumListEntry {
  double timestamp = 0;
  std::string stamp_text;  ///< the timestamp as written (used for ids)
  std::string file;        ///< as written, relative to the list's folder
  int line = 0;
};

/// Parses a list file; throws InputError naming file:line on a malformed line.
std::vector<TumListEntry> parse_tum_list(const std::string& file, const std::string& text);

/// Parses a trajectory; throws InputError naming file:line on a malformed line, a non-finite
/// number, a quaternion far from unit length (|q| outside [0.9, 1.1]) or a timestamp that does not
/// increase.
std::vector<TrajectorySample> parse_tum_trajectory(const std::string& file, const std::string& text);

/// Text of a trajectory, one line per sample, 6 decimals for time, 9 for pose values.
std::string format_tum_trajectory(const std::vector<TrajectorySample>& samples);

}  // namespace olt
