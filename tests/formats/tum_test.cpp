#include "olt/formats/tum.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"

using namespace olt;

TEST_CASE("TUM list files: comments skipped - fields kept") {
  const auto list =
      parse_tum_list("rgb.txt", "# color images\n# timestamp filename\n1.5 rgb/1.5.png\n\n2.25 rgb/2.25.png\n");
  REQUIRE(list.size() == 2);
  CHECK(list[1].timestamp == 2.25);
  CHECK(list[1].file == "rgb/2.25.png");
  CHECK(list[1].line == 5);
}

TEST_CASE("TUM list errors name the line") {
  try {
    parse_tum_list("depth.txt", "1.0 a.png\n0.5 b.png\n");
    FAIL("expected an error");
  } catch (const InputError& e) {
    CHECK(e.diagnostics().at(0).str().rfind("depth.txt:2:1: timestamp 0.5 does not increase", 0) == 0);
  }
  CHECK_THROWS_WITH(parse_tum_list("d.txt", "1.0\n"), Catch::Contains("d.txt:1:1: expected 'timestamp filename'"));
}

TEST_CASE("TUM trajectories parse - validate and format") {
  const auto t = parse_tum_trajectory("gt.txt", "# header\n1.0 1 2 3 0 0 0 1\n2.0 1 2 3 0 0 0.7071068 0.7071068\n");
  REQUIRE(t.size() == 2);
  CHECK(t[1].pose.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  CHECK((t[1].pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-6));
  CHECK(parse_tum_trajectory("x", format_tum_trajectory(t))[1].pose.isApprox(t[1].pose, 1e-8));
  CHECK_THROWS_WITH(parse_tum_trajectory("gt.txt", "1 0 0 0 0 0 0 2\n"),
                    Catch::Contains("gt.txt:1:1: quaternion norm"));
  CHECK_THROWS_WITH(parse_tum_trajectory("gt.txt", "1 0 0 nan 0 0 0 1\n"), Catch::Contains("finite number for tz"));
  CHECK_THROWS_WITH(parse_tum_trajectory("gt.txt", "1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n"),
                    Catch::Contains("gt.txt:2:1: timestamp 1 does not increase"));
}

TEST_CASE("a trajectory with a huge but finite number is written whole and reads back the same") {
  // 1e308 with %.9f is a 320-character number: a line cut at a fixed length would not read back.
  const auto t = parse_tum_trajectory("gt.txt", "1.0 1e308 -2.5e300 3 0 0 0 1\n");
  const std::string text = format_tum_trajectory(t);
  CHECK(text.size() > 600);
  const auto again = parse_tum_trajectory("out.txt", text);
  REQUIRE(again.size() == 1);
  CHECK(again[0].pose.translation().x() == 1e308);
  CHECK(again[0].pose.translation().y() == -2.5e300);
}
