// The preview's projection: points, grid, axes and box outlines where OrthoView says, on a synthetic scene
// (a floor 4 x 3 m at z = 0, a 0.4 m cube on it at x 0.8..1.2, y 0.3..0.7).
#include "olt/reconstruct/preview.h"

#include <catch2/catch.hpp>
#include <limits>
#include <set>

#include "olt/core/box.h"

using namespace olt;

namespace {

const cv::Vec3b kFloor(140, 140, 140);  // BGR
const cv::Vec3b kCube(20, 20, 200);

ColoredCloud floor_and_cube() {
  ColoredCloud cloud;
  for (int i = 0; i <= 200; ++i)
    for (int j = 0; j <= 150; ++j) cloud.push_back({-2.0f + 0.02f * i, -1.5f + 0.02f * j, 0, 140, 140, 140});
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const float a = 0.02f * i, b = 0.02f * j;
      for (const auto& p : {Eigen::Vector3f(0.8f + a, 0.3f + b, 0.4f), Eigen::Vector3f(0.8f + a, 0.3f, b),
                            Eigen::Vector3f(0.8f, 0.3f + a, b), Eigen::Vector3f(1.2f, 0.3f + a, b)})
        cloud.push_back({p.x(), p.y(), p.z(), 200, 20, 20});
    }
  return cloud;
}

PreviewBox cube_box() {
  Box box;
  box.T_world_box.translation() = Eigen::Vector3d(1.0, 0.5, 0.2);
  box.size = Eigen::Vector3d::Constant(0.4);
  return {box_corners(box), {10, 200, 30}, "b1"};
}

}  // namespace

TEST_CASE("preview layout: one scale, x columns shared by the top and front views, grid step from the scale") {
  const Region region = scene_region(floor_and_cube(), 0.25);
  CHECK(region.lo.x() == Approx(-2.25));
  CHECK(region.hi.z() == Approx(0.65));
  const PreviewLayout layout = preview_layout(region, 400);
  CHECK(layout.canvas == cv::Size(800, 400));
  const OrthoView &top = layout.views[0], &front = layout.views[1];
  CHECK(top.px_per_m == front.px_per_m);
  CHECK(layout.grid_step_m * top.px_per_m >= 48);
  CHECK(layout.grid_step_m / 2.5 * top.px_per_m < 48);  // the next smaller step (0.5 for 1, ...) would be too dense
  const Eigen::Vector3d p(1.0, -0.5, 0.3);
  CHECK(front.pixel(p).x - top.pixel(p).x == 400);
  // One metre is px_per_m pixels, up is up.
  CHECK(top.project({1, 0, 0}).x() - top.project({0, 0, 0}).x() == Approx(top.px_per_m));
  CHECK(top.project({0, 1, 0}).y() - top.project({0, 0, 0}).y() == Approx(-top.px_per_m));
  CHECK(front.project({0, 0, 1}).y() - front.project({0, 0, 0}).y() == Approx(-front.px_per_m));
  // The whole region lies in the plots.
  CHECK(top.plot.contains(top.pixel(region.lo)));
  CHECK(front.plot.contains(front.pixel(region.hi - Eigen::Vector3d::Constant(1e-6))));
}

TEST_CASE("scene region: stray points left out, the origin kept in") {
  ColoredCloud cloud;
  for (int i = 0; i < 2000; ++i) cloud.push_back({1 + i / 2000.0f, 1, 1, 0, 0, 0});
  cloud.push_back({100, 1, 1, 0, 0, 0});
  const Region r = scene_region(cloud, 0.1);
  CHECK(r.hi.x() < 2.2);
  CHECK(r.lo.x() == Approx(-0.1));  // the origin, padded
  CHECK(r.hi.y() == Approx(1.1));
}

TEST_CASE("preview: points, grid line x = 1 m and axes from the origin where the projection says") {
  const ColoredCloud cloud = floor_and_cube();
  const PreviewLayout layout = preview_layout(scene_region(cloud, 0.25), 400);
  REQUIRE(layout.grid_step_m == 1.0);
  const cv::Mat image = render_preview(cloud, layout, {0.02, true, ""});
  REQUIRE(image.size() == layout.canvas);
  const OrthoView &top = layout.views[0], &front = layout.views[1];
  auto at = [&](cv::Point p) { return image.at<cv::Vec3b>(p); };

  SECTION("points: the floor and the cube's top, nearest wins") {
    CHECK(at(top.pixel({-1.3, -0.6, 0})) == kFloor);
    CHECK(at(top.pixel({1.05, 0.55, 0.4})) == kCube);
    CHECK(at(front.pixel({1.05, 0, 0.2})) == kCube);
  }
  SECTION("grid: the x = 1 m line darkens the floor in its column only; x = -1 m lightens the empty plot") {
    const cv::Point line = top.pixel({1, -0.75, 0});
    CHECK(at(line) == cv::Vec3b(70, 70, 70));
    CHECK(at(line + cv::Point(-1, 0)) == kFloor);
    CHECK(at(line + cv::Point(1, 0)) == kFloor);
    const cv::Point above = front.pixel({-1, 0, 0.55});
    CHECK(at(above) == cv::Vec3b(157, 157, 157));  // (60 + 255) / 2
    CHECK(at(above + cv::Point(-1, 0)) == cv::Vec3b(60, 60, 60));
  }
  SECTION("axes: x red and y green from the origin in the top view, z blue in the front view, origin ringed") {
    const cv::Point o = top.pixel(Eigen::Vector3d::Zero());
    CHECK(at(o + cv::Point(12, 0)) == cv::Vec3b(40, 40, 235));
    CHECK(at(o + cv::Point(0, -12)) == cv::Vec3b(40, 200, 40));
    CHECK(at(o + cv::Point(7, 0)) == cv::Vec3b(255, 255, 255));
    const cv::Point f = front.pixel(Eigen::Vector3d::Zero());
    CHECK(at(f + cv::Point(0, -12)) == cv::Vec3b(255, 120, 30));
    CHECK(at(f + cv::Point(12, 0)) == cv::Vec3b(40, 40, 235));
  }
}

TEST_CASE("box outline: corners where the projection says, a view's hidden axis collapsed, the name above") {
  const PreviewLayout layout = preview_layout(scene_region(floor_and_cube(), 0.25), 400);
  const OrthoView &top = layout.views[0], &front = layout.views[1];
  const double s = top.px_per_m;
  const BoxOutline from_top = box_outline(top, cube_box()), from_front = box_outline(front, cube_box());
  // Corner 0 is (0.8, 0.3, 0): x to the right of the origin, y (top) or z (front) up from it.
  CHECK(from_top.corners[0].x() == Approx(top.origin_px.x() + 0.8 * s));
  CHECK(from_top.corners[0].y() == Approx(top.origin_px.y() - 0.3 * s));
  CHECK(from_front.corners[0].y() == Approx(front.origin_px.y()));
  CHECK(from_front.corners[7].y() == Approx(front.origin_px.y() - 0.4 * s));  // (1.2, 0.7, 0.4)
  CHECK(from_front.corners[7].x() - from_front.corners[0].x() == Approx(0.4 * s));
  for (int i = 0; i < 8; ++i) {  // the top view does not see z (bit 2), the front view not y (bit 1)
    CHECK((from_top.corners[i & ~4] - from_top.corners[i | 4]).norm() < 1e-9);
    CHECK((from_front.corners[i & ~2] - from_front.corners[i | 2]).norm() < 1e-9);
  }
  // The name beside the highest corner, leftmost of the highest: (0.8, 0.7) in the top view.
  CHECK(from_top.text_at.x() == Approx(top.origin_px.x() + 0.8 * s + 3));
  CHECK(from_top.text_at.y() == Approx(top.origin_px.y() - 0.7 * s - 5));
  // Every edge joins corners one sign apart.
  for (const auto& [a, b] : kBoxEdges) {
    const int differ = a ^ b;
    CHECK((differ == 1 || differ == 2 || differ == 4));
    CHECK(a < b);
  }
}

TEST_CASE("preview: the same cloud gives the same picture, and nothing outside the region is drawn") {
  const ColoredCloud cloud = floor_and_cube();
  const PreviewLayout layout = preview_layout(scene_region(cloud, 0.25), 300);
  const cv::Mat a = render_preview(cloud, layout, {0.02, true, "scene: "});
  const cv::Mat b = render_preview(cloud, layout, {0.02, true, "scene: "});
  CHECK(cv::norm(a, b, cv::NORM_INF) == 0);
  Region above = layout.region;
  above.lo.z() = 0.2;  // the floor and the cube's lower half left out
  PreviewLayout cut = layout;
  cut.region = above;
  const cv::Mat c = render_preview(cloud, cut, {0.02, false, ""});
  CHECK(c.at<cv::Vec3b>(layout.views[0].pixel({-1.3, -0.6, 0})) != kFloor);
  CHECK(c.at<cv::Vec3b>(layout.views[0].pixel({1.05, 0.55, 0.4})) == kCube);
}

TEST_CASE("preview: a box said not to show has no edge near a plot - one that does, or whose name reaches in, shows") {
  const Region crop{Eigen::Vector3d(0.6, 0.1, -0.1), Eigen::Vector3d(1.4, 0.9, 0.6)};  // around the cube
  const PreviewLayout layout = preview_layout(crop, 200, 40);
  auto box_at = [](double x, double y, double z, double side, const std::string& name) {
    Box box;
    box.T_world_box.translation() = Eigen::Vector3d(x, y, z);
    box.size = Eigen::Vector3d::Constant(side);
    return PreviewBox{box_corners(box), {250, 200, 30}, name};
  };
  // Whether a point of the box's edges (every 1/200 of each), widened by its line, lies in a plot.
  auto edge_in_plot = [&](const PreviewBox& box) {
    for (const OrthoView& view : layout.views) {
      const BoxOutline outline = box_outline(view, box);
      for (const auto& [a, b] : kBoxEdges)
        for (int k = 0; k <= 200; ++k) {
          const Eigen::Vector2d p = outline.corners[a] + (outline.corners[b] - outline.corners[a]) * (k / 200.0);
          const double w = box.thickness_px;
          if (p.x() + w > view.plot.x && p.x() - w < view.plot.br().x && p.y() + w > view.plot.y &&
              p.y() - w < view.plot.br().y)
            return true;
        }
    }
    return false;
  };

  CHECK(box_shows(cube_box(), layout));
  CHECK(edge_in_plot(cube_box()));
  const PreviewBox far = box_at(8, 8, 0.2, 0.4, "far");
  CHECK_FALSE(box_shows(far, layout));
  CHECK_FALSE(edge_in_plot(far));
  // Just left of the crop, its edges outside both plots, its long name written into them.
  const PreviewBox named = box_at(0.3, 0.5, 0.2, 0.2, "a_long_name_that_reaches_in");
  CHECK_FALSE(edge_in_plot(named));
  CHECK(box_shows(named, layout));
  PreviewBox unnamed = named;
  unnamed.text.clear();
  CHECK_FALSE(box_shows(unnamed, layout));

  // Boxes all around the crop, near and far, thick and thin: never an edge in a plot from one said
  // not to show.
  int hidden = 0;
  for (int i = 0; i < 120; ++i) {
    const double x = -1.0 + 0.05 * (i * 37 % 80), y = -1.0 + 0.05 * (i * 53 % 60), z = -0.5 + 0.04 * (i % 40);
    PreviewBox box = box_at(x, y, z, 0.05 + 0.01 * (i % 30), i % 3 ? "b" + std::to_string(i) : "");
    box.thickness_px = 1 + i % 3;
    if (box_shows(box, layout)) continue;
    ++hidden;
    INFO("box " << i << " at " << x << " " << y << " " << z);
    CHECK_FALSE(edge_in_plot(box));
  }
  CHECK(hidden > 20);  // the check above ran on many
}

TEST_CASE("preview: drawn through the points ordered by x, every region's picture is the same, byte for byte") {
  // Points of many colours on a coarse lattice (equal depths meet in pixels: the first of equals
  // wins), some exactly on the regions' faces, some with coordinates that are not numbers (drawn
  // nowhere, as no point at all).
  ColoredCloud cloud;
  uint32_t state = 12345;
  const auto next = [&] { return state = state * 1664525u + 1013904223u; };
  for (int i = 0; i < 20000; ++i) {
    const auto coordinate = [&] { return -2.0f + 0.05f * static_cast<float>(next() % 81); };
    const float x = coordinate(), y = coordinate(), z = coordinate();
    cloud.push_back(
        {x, y, z, static_cast<uint8_t>(next()), static_cast<uint8_t>(next()), static_cast<uint8_t>(next())});
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const ColoredCloud not_numbers = {
      {nan, 0.1f, 0.1f, 255, 0, 0}, {0.1f, nan, 0.1f, 0, 255, 0}, {0.1f, 0.1f, nan, 0, 0, 255}};
  cloud.insert(cloud.begin() + 5000, not_numbers.begin(), not_numbers.end());
  const PointsByX by_x = points_by_x(cloud);
  CHECK(by_x.cloud_size == cloud.size());
  CHECK(by_x.by_x.size() == cloud.size() - 1);     // all but the point whose x is not a number
  const double lattice_x = -2.0f + 0.05f * 46.0f;  // 0.3 as the lattice's floats have it
  const std::vector<Region> regions = {
      {Eigen::Vector3d(-2.5, -2.5, -2.5), Eigen::Vector3d(2.5, 2.5, 2.5)},  // every point
      {Eigen::Vector3d(-0.5, -0.5, -0.5), Eigen::Vector3d(0.5, 0.5, 0.5)},  // faces on lattice points
      {Eigen::Vector3d(0.95, -2.0, 0.0), Eigen::Vector3d(1.35, 0.3, 0.7)},
      {Eigen::Vector3d(lattice_x, 0.3, 0.3), Eigen::Vector3d(lattice_x, 1.0, 1.0)},  // one x only
      {Eigen::Vector3d(3.0, 0.0, 0.0), Eigen::Vector3d(4.0, 1.0, 1.0)}};             // no point
  for (const Region& region : regions) {
    const PreviewLayout layout = preview_layout(region, 200);
    const cv::Mat looked_at_all = render_preview(cloud, layout, {0.05, false, ""});
    const cv::Mat through_order = render_preview(cloud, layout, {0.05, false, ""}, &by_x);
    CHECK(cv::norm(looked_at_all, through_order, cv::NORM_INF) == 0);
  }
  // Not the same by luck: the middle region's picture has points of many colours.
  const PreviewLayout middle = preview_layout(regions[1], 200);
  const cv::Mat picture = render_preview(cloud, middle, {0.05, false, ""}, &by_x);
  std::set<uint32_t> colours;
  const cv::Rect plot = middle.views[0].plot;
  for (int v = plot.y; v < plot.br().y; ++v)
    for (int u = plot.x; u < plot.br().x; ++u) {
      const cv::Vec3b p = picture.at<cv::Vec3b>(v, u);
      colours.insert(p[0] << 16 | p[1] << 8 | p[2]);
    }
  CHECK(colours.size() > 100);
  const PreviewLayout one_x = preview_layout(regions[3], 200);
  CHECK(cv::norm(render_preview(cloud, one_x, {0.05, false, ""}, &by_x), render_preview({}, one_x, {0.05, false, ""}),
                 cv::NORM_INF) > 0);  // that region has points
  CHECK(cv::norm(render_preview(not_numbers, middle, {0.05, false, ""}), render_preview({}, middle, {0.05, false, ""}),
                 cv::NORM_INF) == 0);
  // Built from another cloud (not the same size), the order is not used: the picture is still right.
  PointsByX other = by_x;
  other.cloud_size += 1;
  CHECK(cv::norm(render_preview(cloud, middle, {0.05, false, ""}, &other), picture, cv::NORM_INF) == 0);
}
