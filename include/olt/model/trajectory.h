#pragma once
#include <vector>

#include "olt/core/geometry.h"

namespace olt {

/// One sample of a trajectory: the pose (e.g. T_world_sensor) at a time.
struct TrajectorySample {
  double timestamp = 0;  ///< seconds
  Pose pose = Pose::Identity();
};

using Trajectory = std::vector<TrajectorySample>;  ///< timestamps strictly increasing

}  // namespace olt
