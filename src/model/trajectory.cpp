#include "olt/model/trajectory.h"

#include <algorithm>

namespace olt {

bool interpolate_trajectory(const std::vector<TrajectorySample>& trajectory, double t, Pose* pose, double* gap_s) {
  if (trajectory.empty() || t < trajectory.front().timestamp || t > trajectory.back().timestamp) return false;
  auto after = std::lower_bound(trajectory.begin(), trajectory.end(), t,
                                [](const TrajectorySample& s, double time) { return s.timestamp < time; });
  if (after->timestamp == t) {
    *pose = after->pose;
    *gap_s = 0;
    return true;
  }
  const auto before = after - 1;
  const double f = (t - before->timestamp) / (after->timestamp - before->timestamp);
  *pose = interpolate(before->pose, after->pose, f);
  *gap_s = std::min(t - before->timestamp, after->timestamp - t);
  return true;
}

}  // namespace olt
