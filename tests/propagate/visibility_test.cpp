// A box's image in ray space (x/z, y/z), worked out by hand: its outline cut to the depth range,
// and the outline's extent in x within a band of y.
#include "olt/propagate/visibility.h"

#include <catch2/catch.hpp>

using namespace olt;

namespace {

// A 1 m cube centred 2.5 m in front of the camera (z from 2 to 3), square to it.
Box cube_ahead() {
  Box b;
  b.id = "cube";
  b.T_world_box = Pose::Identity();
  b.T_world_box.translation() = Eigen::Vector3d(0, 0, 2.5);
  b.size = Eigen::Vector3d(1, 1, 1);
  return b;
}

// The outline's extent in x and y.
cv::Rect2f extent(const std::vector<cv::Point2f>& outline) {
  float x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const auto& p : outline)
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

TEST_CASE("a box's outline: its near face's square, or the square where the depth range cuts it") {
  // Whole: the near face (z = 2) at +-0.5 / 2 = +-0.25; the far face's corners lie inside it.
  const auto whole = box_outline(cube_ahead(), Pose::Identity(), 0.5, 10);
  CHECK(whole.size() == 4);
  const cv::Rect2f w = extent(whole);
  CHECK(w.x == Approx(-0.25));
  CHECK(w.width == Approx(0.5));
  CHECK(w.y == Approx(-0.25));
  // Cut at z = 2.5: the side edges cross there at +-0.5 / 2.5 = +-0.2.
  const cv::Rect2f cut = extent(box_outline(cube_ahead(), Pose::Identity(), 2.5, 10));
  CHECK(cut.x == Approx(-0.2));
  CHECK(cut.width == Approx(0.4));
  // Beyond the range, or behind the camera: nothing.
  CHECK(box_outline(cube_ahead(), Pose::Identity(), 3.5, 10).empty());
  CHECK(box_outline(cube_ahead(), Pose::Identity(), 0.5, 1.5).empty());
}

TEST_CASE("an outline's x extent within a band of y: at the vertices and where its edges cross the band") {
  // A diamond: (0, -1), (1, 0), (0, 1), (-1, 0).
  const std::vector<cv::Point2f> diamond = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  auto [lo, hi] = outline_x_range(diamond, -0.1f, 0.1f);  // holds the vertices (+-1, 0)
  CHECK(lo == Approx(-1));
  CHECK(hi == Approx(1));
  std::tie(lo, hi) = outline_x_range(diamond, 0.5f, 0.75f);  // edges crossed at y = 0.5: x = +-0.5
  CHECK(lo == Approx(-0.5));
  CHECK(hi == Approx(0.5));
  std::tie(lo, hi) = outline_x_range(diamond, 1.5f, 2.0f);  // above it
  CHECK(lo > hi);
}
