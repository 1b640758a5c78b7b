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

/// The trajectory at time t, translation linearly and rotation by slerp between the samples around
/// it; `gap_s` is the time to the nearer of them. False when t is outside the samples' span.
bool interpolate_trajectory(const Trajectory& trajectory, double t, Pose* pose, double* gap_s);

}  // namespace olt
