#pragma once
// Poses of RGB-D observations from the robot's laser poses (paper Sec. III-C ii): the robot pose at
// the observation's timestamp (plus the sensor's time offset), interpolated along the SE(3)
// geodesic between the scans around it, composed with the sensor's pose on the robot.
// Observations outside the scans' time span, between scans farther apart than `max_scan_gap_s`, or
// next to a scan whose localization failed are flagged (the original toolkit dropped them).
#include <vector>

#include "olt/laser/laser_map.h"
#include "olt/model/recording.h"

namespace olt {

struct LaserPoses {
  std::vector<ObservationPose> poses;  ///< one per observation, in order
  int outside_scans = 0;               ///< flagged: outside the scans' time span
  int in_scan_gaps = 0;                ///< flagged: between scans farther apart than max_scan_gap_s
  int next_to_failed_scans = 0;        ///< flagged: next to a scan whose localization failed
};

LaserPoses poses_from_scans(const std::vector<Observation>& observations, const std::vector<ScanPose>& scans,
                            const Calibration& calibration, double max_scan_gap_s);

}  // namespace olt
