#include "olt/poses/trajectory_poses.h"

#include <algorithm>
#include <cstdio>

namespace olt {

std::vector<ObservationPose> poses_from_trajectory(const std::vector<Observation>& observations,
                                                   const std::vector<TrajectorySample>& trajectory,
                                                   const Calibration& calibration,
                                                   const TrajectoryPosesConfig& config) {
  std::vector<ObservationPose> poses;
  for (const auto& o : observations) {
    ObservationPose p{o.id, o.sensor, o.timestamp, Pose::Identity(), false, "", {}};
    Pose T_world;
    double gap = 0;
    char text[160];
    // The pose source's clock: the observation's timestamp corrected by the sensor's latency.
    const double t = o.timestamp + calibration.at(o.sensor).time_offset_s;
    if (!interpolate_trajectory(trajectory, t, &T_world, &gap)) {
      std::snprintf(text, sizeof(text), "outside the trajectory's time span [%.6f, %.6f]",
                    trajectory.empty() ? 0.0 : trajectory.front().timestamp,
                    trajectory.empty() ? 0.0 : trajectory.back().timestamp);
      p.flag = text;
    } else if (gap > config.max_gap_s) {
      std::snprintf(text, sizeof(text), "nearest trajectory sample %.3f s away (max_gap_s %.3f)", gap,
                    config.max_gap_s);
      p.flag = text;
    } else {
      p.valid = true;
      p.T_world_sensor = config.robot_frame ? T_world * calibration.at(o.sensor).T_robot_sensor : T_world;
    }
    poses.push_back(p);
  }
  return poses;
}

}  // namespace olt
