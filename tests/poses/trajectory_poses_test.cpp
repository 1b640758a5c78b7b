#include "olt/poses/trajectory_poses.h"

#include <catch2/catch.hpp>

using namespace olt;

namespace {

Observation obs(const std::string& id, double t) { return {id, "cam", t, {"d.png", Digest()}, std::nullopt}; }

}  // namespace

TEST_CASE("observation poses are interpolated at their depth timestamps") {
  const Trajectory trajectory = {{10.0, pose_from_xyz_ypr_deg({0, 0, 0, 0, 0, 0})},
                                 {10.1, pose_from_xyz_ypr_deg({1, 0, 0, 40, 0, 0})},
                                 {10.2, pose_from_xyz_ypr_deg({1, 1, 0, 40, 0, 0})}};
  Calibration calibration;
  calibration["cam"].T_robot_sensor = pose_from_xyz_ypr_deg({0, 0, 1, 0, 0, 0});
  const auto poses = poses_from_trajectory({obs("a", 10.025), obs("b", 10.15), obs("c", 9.9), obs("d", 10.3)},
                                           trajectory, calibration, {0.05, false});
  REQUIRE(poses.size() == 4);
  CHECK(poses[0].valid);
  CHECK(poses[0].T_world_sensor.isApprox(pose_from_xyz_ypr_deg({0.25, 0, 0, 10, 0, 0}), 1e-9));
  CHECK(poses[1].T_world_sensor.isApprox(pose_from_xyz_ypr_deg({1, 0.5, 0, 40, 0, 0}), 1e-9));
  CHECK_FALSE(poses[2].valid);
  CHECK_THAT(poses[2].flag, Catch::Contains("outside the trajectory's time span"));
  CHECK_FALSE(poses[3].valid);

  // A gap larger than max_gap_s flags the observation; robot-frame trajectories get the extrinsic.
  const auto strict = poses_from_trajectory({obs("a", 10.05)}, trajectory, calibration, {0.01, true});
  CHECK_FALSE(strict[0].valid);
  CHECK_THAT(strict[0].flag, Catch::Contains("0.050 s away"));
  const auto robot = poses_from_trajectory({obs("a", 10.1)}, trajectory, calibration, {0.05, true});
  CHECK(robot[0].T_world_sensor.translation().isApprox(Eigen::Vector3d(1, 0, 1), 1e-9));
}

TEST_CASE("the sensor's time offset shifts where the trajectory is read") {
  const Trajectory trajectory = {{10.0, pose_from_xyz_ypr_deg({0, 0, 0, 0, 0, 0})},
                                 {10.1, pose_from_xyz_ypr_deg({1, 0, 0, 40, 0, 0})}};
  Calibration calibration;
  calibration["cam"].time_offset_s = -0.025;  // the image was taken 25 ms before its timestamp
  const auto poses = poses_from_trajectory({obs("a", 10.05)}, trajectory, calibration, {0.05, false});
  REQUIRE(poses[0].valid);
  CHECK(poses[0].timestamp == 10.05);
  CHECK(poses[0].T_world_sensor.isApprox(pose_from_xyz_ypr_deg({0.25, 0, 0, 10, 0, 0}), 1e-9));
}
