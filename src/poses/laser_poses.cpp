#include "olt/poses/laser_poses.h"

#include <algorithm>
#include <cstdio>

namespace olt {

LaserPoses poses_from_scans(const std::vector<Observation>& observations, const std::vector<ScanPose>& scans,
                            const Calibration& calibration, double max_scan_gap_s) {
  LaserPoses out;
  std::vector<ObservationPose>& poses = out.poses;
  for (const auto& o : observations) {
    ObservationPose p{o.id, o.sensor, o.timestamp, Pose::Identity(), false, "", {}};
    const SensorCalibration& cal = calibration.at(o.sensor);
    const double t = o.timestamp + cal.time_offset_s;
    const auto after = std::lower_bound(scans.begin(), scans.end(), t,
                                        [](const ScanPose& s, double time) { return s.timestamp < time; });
    char text[200];
    if (scans.empty() || after == scans.end() || (after == scans.begin() && after->timestamp > t)) {
      std::snprintf(text, sizeof(text), "outside the laser scans' time span [%.6f, %.6f]",
                    scans.empty() ? 0.0 : scans.front().timestamp, scans.empty() ? 0.0 : scans.back().timestamp);
      p.flag = text;
      ++out.outside_scans;
      poses.push_back(p);
      continue;
    }
    const auto before = after->timestamp == t || after == scans.begin() ? after : after - 1;
    const size_t i = static_cast<size_t>(before - scans.begin()), j = static_cast<size_t>(after - scans.begin());
    p.quality.laser = ScanQuality{i, j, after->timestamp - before->timestamp};
    if (after->timestamp - before->timestamp > max_scan_gap_s) {
      std::snprintf(text, sizeof(text), "the scans around it are %.3f s apart (max_scan_gap_s %.3f)",
                    after->timestamp - before->timestamp, max_scan_gap_s);
      p.flag = text;
      ++out.in_scan_gaps;
    } else if (!before->valid || !after->valid) {
      std::snprintf(text, sizeof(text), "next to a failed scan localization (scan %zu: %s)", before->valid ? j : i,
                    (before->valid ? after : before)->flag.c_str());
      p.flag = text;
      ++out.next_to_failed_scans;
    } else {
      const double f = j == i ? 0.0 : (t - before->timestamp) / (after->timestamp - before->timestamp);
      const Pose T_world_robot = interpolate_geodesic(to_pose3(before->T_map_robot), to_pose3(after->T_map_robot), f);
      p.T_world_sensor = T_world_robot * cal.T_robot_sensor;
      p.valid = true;
    }
    poses.push_back(p);
  }
  return out;
}

}  // namespace olt
