#include "olt/poses/laser_poses.h"

#include <catch2/catch.hpp>

using namespace olt;

namespace {

ScanPose scan_at(double t, double x, double y, double heading_deg, bool valid = true) {
  ScanPose s;
  s.timestamp = t;
  s.T_map_robot = pose2(x, y, heading_deg * M_PI / 180);
  s.valid = valid;
  if (!valid) s.flag = "scan match failed";
  return s;
}

Observation observation(const std::string& id, double t) { return {id, "cam", t, {}, std::nullopt}; }

}  // namespace

TEST_CASE("laser poses: the robot pose on the arc between the scans, composed with the camera on the robot") {
  // The robot turns 90 degrees left while going from (0, 0) to (1, 1): a quarter circle around
  // (0, 1). The camera sits 0.2 m ahead and 1 m up, looking along the robot's y axis.
  const std::vector<ScanPose> scans = {scan_at(10, 0, 0, 0), scan_at(11, 1, 1, 90), scan_at(12, 1, 2, 90)};
  Calibration calibration;
  calibration["cam"].T_robot_sensor = pose_from_xyz_ypr_deg({0.2, 0, 1, 90, 0, 0});
  calibration["cam"].time_offset_s = 0.1;  // its clock runs 0.1 s behind the laser's
  const auto poses = poses_from_scans({observation("a", 10.4), observation("b", 12)}, scans, calibration, 1.0).poses;
  REQUIRE(poses.size() == 2);
  REQUIRE(poses[0].valid);
  // At 10.5 s: 45 degrees, at (sin 45, 1 - cos 45); the camera 0.2 m ahead along the 45 degree
  // heading, 1 m up, yawed 135 degrees in all.
  const double h = std::sqrt(0.5);
  const Pose expected = pose_from_xyz_ypr_deg({h + 0.2 * h, 1 - h + 0.2 * h, 1, 135, 0, 0});
  CHECK(poses[0].T_world_sensor.isApprox(expected, 1e-9));
  // At 12.1 s (after the last scan): outside.
  CHECK_FALSE(poses[1].valid);
  CHECK(poses[1].flag.rfind("outside the laser scans' time span", 0) == 0);
}

TEST_CASE("laser poses: observations next to a failed scan or between distant scans are flagged, not dropped") {
  const std::vector<ScanPose> scans = {scan_at(10, 0, 0, 0), scan_at(10.1, 0.1, 0, 0, false), scan_at(10.2, 0.2, 0, 0),
                                       scan_at(13, 1, 0, 0), scan_at(13.1, 1.1, 0, 0)};
  Calibration calibration;
  calibration["cam"];
  const LaserPoses placed =
      poses_from_scans({observation("before", 9.9), observation("failed", 10.05), observation("fine", 10.2),
                        observation("gap", 12), observation("ok", 13.05)},
                       scans, calibration, 1.0);
  CHECK(placed.outside_scans == 1);
  CHECK(placed.next_to_failed_scans == 1);
  CHECK(placed.in_scan_gaps == 1);
  const auto& poses = placed.poses;
  REQUIRE(poses.size() == 5);
  CHECK_FALSE(poses[0].valid);
  CHECK_FALSE(poses[1].valid);
  CHECK(poses[1].flag == "next to a failed scan localization (scan 1: scan match failed)");
  CHECK(poses[2].valid);  // exactly at a good scan
  CHECK(poses[2].T_world_sensor.translation().isApprox(Eigen::Vector3d(0.2, 0, 0)));
  CHECK_FALSE(poses[3].valid);
  CHECK(poses[3].flag == "the scans around it are 2.800 s apart (max_scan_gap_s 1.000)");
  CHECK(poses[4].valid);
  CHECK(poses[4].T_world_sensor.translation().isApprox(Eigen::Vector3d(1.05, 0, 0)));
}
