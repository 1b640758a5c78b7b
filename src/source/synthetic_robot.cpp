// The synthetic robot: the Robot@Home rig of RGB-D cameras, a clockwise loop around the table, a 2D
// laser scan every 0.1 s with range noise, and wheel odometry that drifts.
#include <algorithm>
#include <cmath>

#include "olt/core/geometry.h"
#include "synthetic_parts.h"

namespace olt {
namespace {

// The Robot@Home rig (x y z in metres, yaw pitch roll in degrees; MRPT's camera frame: x forward,
// y left, z up; roll -90: the cameras are mounted on their side). The laser HOKUYO1 at
// (0.205, 0, 0.31).
constexpr double kRig[4][6] = {{0.285, 0, 1.015, 0, 1.3, -90},
                               {0.271, -0.031, 1.015, -45, 0, -90},
                               {0.271, 0.031, 1.125, 45, 2, -89},
                               {0.24, -0.045, 0.975, -90, 1.5, -90}};
const Eigen::Vector3d kLaserOnRobot(0.205, 0, 0.31);

// The camera's optical frame (x right, y down, z forward) on the robot.
Pose rig_camera(int c) {
  const auto& r = kRig[c];
  return pose_from_xyz_ypr_deg({r[0], r[1], r[2], r[3], r[4], r[5]}) * mrpt_camera_from_optical();
}

// The robot drives clockwise around the table on an ellipse (2.3 x 1.85 m), 0.19 rad/s (about
// 0.4 m/s), heading along its path; at t = 0 it is at (0, -1.85) heading -x.
constexpr double kPathA = 2.3, kPathB = 1.85, kPathRate = 0.19;

Pose robot_pose(double t) {
  const double phi = -M_PI / 2 - kPathRate * (t - kStartTime);
  const double heading = std::atan2(-kPathB * std::cos(phi), kPathA * std::sin(phi));
  return to_pose3(pose2(kPathA * std::cos(phi), kPathB * std::sin(phi), heading));
}

LaserScan laser_scan(const std::vector<Box>& objects, double t, int index, std::mt19937& rng) {
  LaserScan scan;
  scan.index = index;
  scan.timestamp = t;
  scan.T_robot_laser = Pose::Identity();
  scan.T_robot_laser.translation() = kLaserOnRobot;
  scan.aperture_rad = 240 * M_PI / 180;
  scan.max_range_m = 5.6;
  const size_t rays = 481;
  scan.ranges.resize(rays);
  scan.valid.resize(rays);
  std::normal_distribution<double> noise(0, 0.01);
  const Pose T = robot_pose(t) * scan.T_robot_laser;
  const RayTracer tracer(objects);
  for (size_t k = 0; k < rays; ++k) {
    const double a = scan.ray_angle(k);
    const Hit hit = tracer.cast(T.translation(), T.linear() * Eigen::Vector3d(std::cos(a), std::sin(a), 0));
    const double r = hit.t + noise(rng);
    scan.valid[k] = r <= scan.max_range_m;
    scan.ranges[k] = static_cast<float>(scan.valid[k] ? r : scan.max_range_m);
  }
  return scan;
}

}  // namespace

void make_robot(SyntheticScene& scene, std::mt19937& rng) {
  const SyntheticConfig& config = scene.config;
  for (int c = 0; c < config.cameras; ++c) {
    scene.sensors.push_back("RGBD_" + std::to_string(c + 1));
    scene.T_robot_camera.push_back(rig_camera(c));
  }
  // Camera c's k-th observation at 0.1 + 0.025 c + k / rate seconds: the cameras are not in step
  // with each other or with the laser.
  struct Shot {
    double t;
    int camera;
  };
  std::vector<Shot> shots;
  for (int c = 0; c < config.cameras; ++c)
    for (int k = 0; k < config.frames; ++k) shots.push_back({kStartTime + 0.1 + 0.025 * c + k / config.rate_hz, c});
  std::sort(shots.begin(), shots.end(), [](const Shot& a, const Shot& b) { return a.t < b.t; });
  for (const auto& s : shots) {
    const double color_dt = scene.timestamps.size() % 2 ? -config.color_dt_s : config.color_dt_s;
    scene.timestamps.push_back(s.t);
    scene.camera_of.push_back(s.camera);
    scene.T_world_camera.push_back(robot_pose(s.t) * scene.T_robot_camera[s.camera]);
    scene.color_dt_s.push_back(color_dt);
    scene.T_world_color.push_back(robot_pose(s.t + color_dt) * scene.T_robot_camera[s.camera]);
  }
  const double end = shots.back().t + 0.3;
  for (double t = kStartTime - 0.5; t <= end + 0.5; t += 0.01) scene.robot_truth.push_back({t, robot_pose(t)});
  // Laser at 10 Hz; odometry 5 ms before each scan, integrated from increments that are 1.5 % too
  // long, turn 2 % too little, drift 0.01 rad per metre, with a little noise.
  std::normal_distribution<double> step_noise(0, 0.001);
  Pose2 odometry = Pose2::Identity();
  Pose2 previous_truth = to_pose2(robot_pose(kStartTime - 0.005));
  for (int j = 0; kStartTime + 0.1 * j <= end; ++j) {
    const double t = kStartTime + 0.1 * j;
    const Pose2 truth = to_pose2(robot_pose(t - 0.005));
    const Pose2 d = previous_truth.inverse() * truth;
    const double dx = d.translation().x(), dy = d.translation().y();
    odometry = odometry * pose2(1.015 * dx + step_noise(rng), 1.015 * dy + step_noise(rng),
                                0.98 * heading(d) + 0.01 * std::hypot(dx, dy) + step_noise(rng));
    previous_truth = truth;
    scene.odometry.push_back({t - 0.005, odometry});
    scene.scans.push_back(laser_scan(scene.objects, t, j, rng));
  }
}

}  // namespace olt
