#include "olt/laser/scan_matching.h"

#include <catch2/catch.hpp>
#include <random>

#include "support/laser_world.h"

using namespace olt;
using namespace olt::test;

TEST_CASE("scan matching recovers a known 2D transform from a guess off by 30 cm and 8 degrees") {
  const std::vector<Segment> world = l_shaped_room();
  // The map: a scan from the origin, its points with normals.
  const std::vector<Eigen::Vector2d> reference = cast_scan(world, pose2(0, 0, 0), 0);
  PointMap2D map(0.02);
  map.add(reference, scan_normals(reference));
  map.build();
  // The scan from a known pose, matched from the identity.
  const Pose2 truth = pose2(0.25, -0.15, 8 * M_PI / 180);
  const std::vector<Eigen::Vector2d> scan = cast_scan(world, truth, 0);
  const ScanMatch m = match_scan(map, scan, Pose2::Identity(), ScanMatchSettings{});
  CHECK(m.converged);
  CHECK((m.T_map_robot.translation() - truth.translation()).norm() < 0.001);
  CHECK(std::abs(heading(m.T_map_robot) - heading(truth)) * 180 / M_PI < 0.05);
  CHECK(m.inlier_ratio > 0.9);
  // The guess alone is far off: the match did the work.
  CHECK(truth.translation().norm() > 0.25);
}

TEST_CASE("scan matching with 1 cm range noise and 10% outliers (people) stays within 1 cm and 0.2 degrees") {
  const std::vector<Segment> world = l_shaped_room();
  const std::vector<Eigen::Vector2d> reference = cast_scan(world, pose2(0, 0, 0), 0.01, 1);
  PointMap2D map(0.02);
  map.add(reference, scan_normals(reference));
  map.build();
  const Pose2 truth = pose2(-0.2, 0.3, -6 * M_PI / 180);
  std::vector<Eigen::Vector2d> scan = cast_scan(world, truth, 0.01, 2);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> near(0.3, 1.5);
  for (size_t i = 0; i < scan.size(); i += 10) scan[i] *= near(rng) / scan[i].norm();  // something in the way
  const ScanMatch m = match_scan(map, scan, Pose2::Identity(), ScanMatchSettings{});
  CHECK((m.T_map_robot.translation() - truth.translation()).norm() < 0.01);
  CHECK(std::abs(heading(m.T_map_robot) - heading(truth)) * 180 / M_PI < 0.2);
}

TEST_CASE("scan normals: perpendicular to walls, none at isolated points") {
  const std::vector<Eigen::Vector2d> wall = {{1, -0.1}, {1, -0.05}, {1, 0}, {1, 0.05}, {1, 0.1}, {3, 2}};
  const auto normals = scan_normals(wall);
  CHECK(std::abs(normals[2].x()) == Approx(1));
  CHECK(normals[2].y() == Approx(0).margin(1e-9));
  CHECK(normals[5].squaredNorm() == 0);
}
