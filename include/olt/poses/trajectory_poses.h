#pragma once
// Poses of observations from an imported trajectory (PRODUCT.md, poses (c)): each observation's
// pose is the trajectory interpolated at its depth timestamp, translation linearly and rotation by
// slerp. Observations outside the trajectory's span, or too far in time from a sample, are flagged.
#include <string>
#include <vector>

#include "olt/model/recording.h"
#include "olt/model/trajectory.h"

namespace olt {

struct TrajectoryPosesConfig {
  double max_gap_s = 0.05;   ///< largest time from an observation to the nearest trajectory sample, seconds
  bool robot_frame = false;  ///< the trajectory gives T_world_robot (compose with the extrinsic), not T_world_sensor
};

std::vector<ObservationPose> poses_from_trajectory(const std::vector<Observation>& observations,
                                                   const std::vector<TrajectorySample>& trajectory,
                                                   const Calibration& calibration, const TrajectoryPosesConfig& config);

}  // namespace olt
