#pragma once
// What a robot's 2D laser and wheel odometry record: planar scans with the scanner's pose on the
// robot, and odometry poses (x, y, heading) integrated from the robot's start.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "olt/core/geometry.h"

namespace olt {

using Pose2 = Eigen::Isometry2d;  ///< planar rigid transform (x, y, heading)

Pose2 pose2(double x, double y, double heading_rad);
double heading(const Pose2& pose);  ///< radians, (-pi, pi]
/// The planar pose lifted to 3D (z = 0, rotation about z), and a 3D pose projected to the plane.
Pose to_pose3(const Pose2& pose);
Pose2 to_pose2(const Pose& pose);

struct LaserScan {
  int index = 0;                          ///< as the file numbers it
  double timestamp = 0;                   ///< seconds
  Pose T_robot_laser = Pose::Identity();  ///< the scanner on the robot (x, y, z, yaw)
  double aperture_rad = M_PI;             ///< field of view
  bool right_to_left = true;              ///< ray k at -aperture/2 + k * step (else the reverse)
  double max_range_m = 80;                ///< the scanner's range
  std::vector<float> ranges;              ///< metres, one per ray
  std::vector<uint8_t> valid;             ///< 1 where the ray returned

  /// The angle of ray k in the scanner frame, radians.
  double ray_angle(size_t k) const;
};

/// The valid returns of `scan` between min_range_m and max_range_m (and short of the scanner's own
/// maximum), as points in the robot frame (the scanner's pose on the robot applied, in the plane).
std::vector<Eigen::Vector2d> scan_points(const LaserScan& scan, double min_range_m, double max_range_m);

struct OdometrySample {
  double timestamp = 0;            ///< seconds
  Pose2 pose = Pose2::Identity();  ///< integrated from the start, odometry frame
};

/// The odometry pose at time t: linear in x, y and the unwrapped heading between the samples around
/// it, held at the first or last sample outside their span. Identity for empty odometry.
Pose2 odometry_at(const std::vector<OdometrySample>& odometry, double t);

}  // namespace olt
