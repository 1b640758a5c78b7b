#include "olt/model/laser.h"

#include <algorithm>
#include <cmath>

namespace olt {

Pose2 pose2(double x, double y, double heading_rad) {
  Pose2 p = Pose2::Identity();
  p.linear() = Eigen::Rotation2Dd(heading_rad).toRotationMatrix();
  p.translation() = Eigen::Vector2d(x, y);
  return p;
}

double heading(const Pose2& pose) { return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)); }

Pose to_pose3(const Pose2& pose) {
  Pose p = Pose::Identity();
  p.linear() = Eigen::AngleAxisd(heading(pose), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(pose.translation().x(), pose.translation().y(), 0);
  return p;
}

Pose2 to_pose2(const Pose& pose) {
  const Eigen::Vector3d x_axis = pose.linear().col(0);
  return pose2(pose.translation().x(), pose.translation().y(), std::atan2(x_axis.y(), x_axis.x()));
}

double LaserScan::ray_angle(size_t k) const {
  const double step = ranges.size() > 1 ? aperture_rad / static_cast<double>(ranges.size() - 1) : 0;
  const double a = -aperture_rad / 2 + static_cast<double>(k) * step;
  return right_to_left ? a : -a;
}

std::vector<Eigen::Vector2d> scan_points(const LaserScan& scan, double min_range_m, double max_range_m) {
  const Pose2 T = to_pose2(scan.T_robot_laser);
  // Readings at the scanner's own maximum are "nothing seen", not a wall.
  const double far = std::min(max_range_m, scan.max_range_m * 0.99);
  std::vector<Eigen::Vector2d> points;
  points.reserve(scan.ranges.size());
  for (size_t k = 0; k < scan.ranges.size(); ++k) {
    const double r = scan.ranges[k];
    if ((k < scan.valid.size() && !scan.valid[k]) || !std::isfinite(r) || r < min_range_m || r > far) continue;
    const double a = scan.ray_angle(k);
    points.push_back(T * Eigen::Vector2d(r * std::cos(a), r * std::sin(a)));
  }
  return points;
}

Pose2 odometry_at(const std::vector<OdometrySample>& odometry, double t) {
  if (odometry.empty()) return Pose2::Identity();
  if (t <= odometry.front().timestamp) return odometry.front().pose;
  if (t >= odometry.back().timestamp) return odometry.back().pose;
  const auto next = std::upper_bound(odometry.begin(), odometry.end(), t,
                                     [](double time, const OdometrySample& s) { return time < s.timestamp; });
  const auto& b = *next;
  const auto& a = *(next - 1);
  const double f = (t - a.timestamp) / (b.timestamp - a.timestamp);
  const Eigen::Vector2d p = (1 - f) * a.pose.translation() + f * b.pose.translation();
  const double ha = heading(a.pose), turn = std::remainder(heading(b.pose) - ha, 2 * M_PI);
  return pose2(p.x(), p.y(), ha + f * turn);
}

}  // namespace olt
