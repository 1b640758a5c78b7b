#include "olt/formats/laser_text.h"

#include <catch2/catch.hpp>
#include <limits>

#include "olt/core/error.h"

using namespace olt;

namespace {

std::string error_of(const std::string& text) {
  try {
    parse_laser_scans("scans.txt", text);
  } catch (const InputError& e) {
    return e.diagnostics().front().str();
  }
  return "";
}

}  // namespace

TEST_CASE("laser scans: rays, validity and the scanner's pose read as written") {
  // 3 rays over 90 degrees from right to left: -45, 0, +45 degrees; the scanner 0.5 m ahead of the
  // robot and turned 90 degrees left.
  const auto scans = parse_laser_scans(
      "scans.txt", "# comment\n7 100.25 0.5 0 0.3 1.5707963267948966 1.5707963267948966 1 30 3 1.0 2.0 30.0 1 1 0\n");
  REQUIRE(scans.size() == 1);
  const LaserScan& s = scans[0];
  CHECK(s.index == 7);
  CHECK(s.timestamp == 100.25);
  CHECK(s.ray_angle(0) == Approx(-M_PI / 4));
  CHECK(s.ray_angle(2) == Approx(M_PI / 4));
  CHECK(s.T_robot_laser.translation().isApprox(Eigen::Vector3d(0.5, 0, 0.3)));
  // The invalid third ray is dropped; ray 1 (2 m straight ahead of the scanner) is 2 m to the
  // robot's left, 0.5 m ahead; ray 0 (1 m at -45 degrees) is at 45 degrees left-forward.
  const auto points = scan_points(s, 0.1, 100);
  REQUIRE(points.size() == 2);
  CHECK(points[1].isApprox(Eigen::Vector2d(0.5, 2.0), 1e-9));
  CHECK(points[0].isApprox(Eigen::Vector2d(0.5 + std::sqrt(0.5), std::sqrt(0.5)), 1e-9));
  // Written and read back: the same scan.
  const auto again = parse_laser_scans("again.txt", format_laser_scans(scans));
  REQUIRE(again.size() == 1);
  CHECK(again[0].ranges == s.ranges);
  CHECK(again[0].valid == s.valid);
  CHECK(again[0].T_robot_laser.isApprox(s.T_robot_laser, 1e-6));
}

TEST_CASE("laser scans: malformed lines are named by file and line") {
  CHECK(error_of("0 1 0 0 0 0 3.14 1 80 2 1.0 1.0 1\n") == "scans.txt:1:1: N = 2 rays needs 14 fields, got 13");
  CHECK(error_of("\n0 1 0 0 0 0 3.14 1 80 0\n").rfind("scans.txt:2:1: N (rays) must be an integer", 0) == 0);
  CHECK(error_of("0 1 0 0 0 0 3.14 1 80 1 1.0 2\n") == "scans.txt:1:1: valid[0] must be 0 or 1, got '2'");
  CHECK(error_of("0 1 0 0 0 0 3.14 1 80 1 nan 1\n") ==
        "scans.txt:1:1: expected a finite number for range 0, got 'nan'");
  CHECK(error_of("0 2 0 0 0 0 3.14 1 80 1 1 1\n1 2 0 0 0 0 3.14 1 80 1 1 1\n")
            .rfind("scans.txt:2:1: timestamp 2.000000 does not increase (previous line 1)", 0) == 0);
  CHECK(error_of("0 1 0 0 0 0 3.14 1 80\n").rfind("scans.txt:1:1: expected 'idx timestamp", 0) == 0);
  CHECK(error_of("0 1 0 0 0 0 0 1 80 1 1 1\n") == "scans.txt:1:1: aperture_rad must be in (0, 2 pi], got '0'");
}

TEST_CASE("odometry: poses read, interpolated on the unwrapped heading, held outside the samples") {
  const auto odometry = parse_odometry("odo.txt", "0 10 0 0 3.0\n1 11 1 0 -3.0\n");
  REQUIRE(odometry.size() == 2);
  // From +3.0 rad to -3.0 rad is a 0.283 rad turn through pi, not 6 rad the other way.
  const Pose2 mid = odometry_at(odometry, 10.5);
  CHECK(mid.translation().isApprox(Eigen::Vector2d(0.5, 0)));
  CHECK(std::remainder(heading(mid) - (3.0 + (2 * M_PI - 6.0) / 2), 2 * M_PI) == Approx(0).margin(1e-12));
  CHECK(odometry_at(odometry, 5).translation().isApprox(Eigen::Vector2d(0, 0)));
  CHECK(odometry_at(odometry, 20).translation().isApprox(Eigen::Vector2d(1, 0)));
  CHECK_THROWS_WITH(parse_odometry("odo.txt", "0 10 0 0\n"),
                    "odo.txt:1:1: expected 'idx timestamp x y theta', got 4 fields");
}

TEST_CASE(
    "scans from elsewhere: upside-down scanners become level ones scanning the other way, tilted ones are refused") {
  LaserScan s;
  s.aperture_rad = M_PI / 2;
  s.max_range_m = 10;
  s.ranges = {1.0f, 2.0f, std::numeric_limits<float>::infinity()};
  s.valid = {1, 1, 1};
  s.T_robot_laser = pose_from_xyz_ypr_deg({0.3, 0, 0.2, 0, 0, 180});  // rolled half a turn
  const LaserScan original = s;
  REQUIRE(check_scan(s).empty());
  CHECK(s.valid == std::vector<uint8_t>{1, 1, 0});  // the infinite range
  CHECK_FALSE(s.right_to_left);
  // The first ray, at -45 degrees in the rolled scanner's frame, is at +45 degrees (left) seen from
  // above: the same point before and after.
  const Eigen::Vector3d seen = original.T_robot_laser * Eigen::Vector3d(std::cos(-M_PI / 4), std::sin(-M_PI / 4), 0);
  const auto points = scan_points(s, 0.1, 100);
  REQUIRE(points.size() == 2);
  CHECK(points[0].isApprox(seen.head<2>(), 1e-9));
  CHECK(seen.y() > 0);
  LaserScan tilted = original;
  tilted.T_robot_laser = pose_from_xyz_ypr_deg({0, 0, 0, 0, 20, 0});
  CHECK(check_scan(tilted).find("tilted 20.0") != std::string::npos);
  LaserScan empty = original;
  empty.ranges.clear();
  CHECK(check_scan(empty) == "a scan must have 1 to 100000 rays");
}
