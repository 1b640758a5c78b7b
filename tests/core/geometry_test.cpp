#include "olt/core/geometry.h"

#include <catch2/catch.hpp>

#include "olt/core/box.h"

using namespace olt;

TEST_CASE("yaw-pitch-roll is intrinsic Z-Y'-X''") {
  // yaw 90: x -> y
  const Eigen::Vector3d x = rotation_from_ypr_deg(90, 0, 0) * Eigen::Vector3d::UnitX();
  CHECK(x.isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  // pitch 90 about y: x -> -z
  CHECK((rotation_from_ypr_deg(0, 90, 0) * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
  // roll 90 about x: y -> z
  CHECK((rotation_from_ypr_deg(0, 0, 90) * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  // yaw 90 then roll 90 about the *new* x (which is world y): the box's y axis (world -x after yaw)
  // turns to world z.
  const Eigen::Matrix3d R = rotation_from_ypr_deg(90, 0, 90);
  CHECK((R * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  CHECK((R * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

TEST_CASE("interpolation: translation linear - rotation by slerp") {
  const Pose a = pose_from_xyz_ypr_deg({0, 0, 0, 0, 0, 0});
  const Pose b = pose_from_xyz_ypr_deg({2, -4, 6, 90, 0, 0});
  const Pose mid = interpolate(a, b, 0.25);
  CHECK(mid.translation().isApprox(Eigen::Vector3d(0.5, -1, 1.5), 1e-12));
  // a quarter of the way from 0 to 90 degrees about z is 22.5 degrees about z
  CHECK(mid.linear().isApprox(rotation_from_ypr_deg(22.5, 0, 0), 1e-12));
  CHECK(interpolate(a, b, 0).isApprox(a));
  CHECK(interpolate(a, b, 1).isApprox(b));
}

TEST_CASE("pose JSON is [tx ty tz qx qy qz qw] with qw >= 0 and round-trips") {
  const Pose p = pose_from_xyz_ypr_deg({1, 2, 3, 200, 10, -30});
  const auto j = pose_to_json(p);
  REQUIRE(j.size() == 7);
  CHECK(j[6].get<double>() >= 0);
  CHECK(pose_from_json(j).isApprox(p, 1e-12));
}

TEST_CASE("point in an oriented box - hand-placed points") {
  Box box;
  box.size = Eigen::Vector3d(2, 1, 0.5);
  box.T_world_box = pose_from_xyz_ypr_deg({10, 0, 1, 90, 0, 0});  // long axis along world y
  CHECK(contains(box, Eigen::Vector3d(10, 0, 1)));
  CHECK(contains(box, Eigen::Vector3d(10, 0.99, 1)));        // along the long axis (now world y)
  CHECK_FALSE(contains(box, Eigen::Vector3d(10.99, 0, 1)));  // world x is the short axis (half 0.5)
  CHECK(contains(box, Eigen::Vector3d(10.49, -0.99, 1.24)));
  CHECK_FALSE(contains(box, Eigen::Vector3d(10, 0, 1.26)));
  CHECK(contains(box, Eigen::Vector3d(10.5, 1.0, 1.25)));  // a corner is inside (closed box)
  const auto corners = box_corners(box);
  // corner 0 has local (-1, -0.5, -0.25); yaw 90 maps local x to world y, local y to world -x
  CHECK(corners[0].isApprox(Eigen::Vector3d(10.5, -1, 0.75), 1e-12));
  CHECK(corners[7].isApprox(Eigen::Vector3d(9.5, 1, 1.25), 1e-12));
}

TEST_CASE("geodesic interpolation follows the screw motion: a planar quarter turn is a circular arc") {
  // From the origin heading +x to (1, 1) heading +y at constant velocity: the quarter circle of
  // radius 1 around (0, 1). Halfway: 45 degrees, at (sin 45, 1 - cos 45).
  const Pose a = Pose::Identity();
  const Pose b = pose_from_xyz_ypr_deg({1, 1, 0, 90, 0, 0});
  const Pose mid = interpolate_geodesic(a, b, 0.5);
  CHECK(mid.translation().isApprox(Eigen::Vector3d(std::sqrt(0.5), 1 - std::sqrt(0.5), 0), 1e-12));
  CHECK(mid.linear().isApprox(rotation_from_ypr_deg(45, 0, 0), 1e-12));
  // A third of the way: 30 degrees, at (sin 30, 1 - cos 30); the chord (linear) would be at (1/3, 1/3).
  const Pose third = interpolate_geodesic(a, b, 1.0 / 3);
  CHECK(third.translation().isApprox(Eigen::Vector3d(0.5, 1 - std::sqrt(3) / 2, 0), 1e-12));
  // Ends and a pure translation.
  CHECK(interpolate_geodesic(a, b, 0).isApprox(a, 1e-12));
  CHECK(interpolate_geodesic(a, b, 1).isApprox(b, 1e-12));
  const Pose c = pose_from_xyz_ypr_deg({2, -4, 6, 0, 0, 0});
  CHECK(interpolate_geodesic(a, c, 0.25).translation().isApprox(Eigen::Vector3d(0.5, -1, 1.5), 1e-12));
  // Not at the origin: the same arc seen from a moved and turned start.
  const Pose start = pose_from_xyz_ypr_deg({3, -2, 0.5, 30, 10, -5});
  CHECK(interpolate_geodesic(start * a, start * b, 0.5).isApprox(start * mid, 1e-12));
}
