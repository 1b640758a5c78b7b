#include "olt/propagate/visibility.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <tuple>

namespace olt {

DepthView make_depth_view(const Intrinsics& camera) {
  DepthView view;
  view.width = camera.width;
  view.height = camera.height;
  view.rays = pixel_rays(camera);
  view.column_min_x.assign(camera.width, INFINITY);
  view.column_max_x.assign(camera.width, -INFINITY);
  view.row_min_y.assign(camera.height, INFINITY);
  view.row_max_y.assign(camera.height, -INFINITY);
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector2f& r = view.rays[static_cast<size_t>(v) * camera.width + u];
      view.column_min_x[u] = std::min(view.column_min_x[u], r.x());
      view.column_max_x[u] = std::max(view.column_max_x[u], r.x());
      view.row_min_y[v] = std::min(view.row_min_y[v], r.y());
      view.row_max_y[v] = std::max(view.row_max_y[v], r.y());
    }
  view.row_x_ascending.assign(camera.height, 1);
  for (int v = 0; v < camera.height; ++v)
    for (int u = 1; u < camera.width; ++u) {
      const size_t i = static_cast<size_t>(v) * camera.width + u;
      if (!(view.rays[i - 1].x() <= view.rays[i].x())) view.row_x_ascending[v] = 0;
    }
  return view;
}

std::shared_ptr<const DepthView> shared_depth_view(const Intrinsics& c) {
  using Key = std::tuple<int, int, double, double, double, double, std::array<double, 5>>;
  static std::mutex mutex;
  static std::map<Key, std::shared_ptr<const DepthView>> made;
  const Key key{c.width, c.height, c.fx, c.fy, c.cx, c.cy, c.distortion};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (auto it = made.find(key); it != made.end()) return it->second;
  }
  auto view = std::make_shared<const DepthView>(make_depth_view(c));  // outside the lock: it is slow
  const std::lock_guard<std::mutex> lock(mutex);
  if (made.size() >= 16) made.clear();
  return made.emplace(key, std::move(view)).first->second;
}

namespace {

// First and last index whose [lo, hi] range meets [a, b]; {1, 0} when none does.
std::pair<int, int> overlapping(const std::vector<float>& lo, const std::vector<float>& hi, double a, double b) {
  int first = -1, last = -1;
  for (int i = 0; i < static_cast<int>(lo.size()); ++i)
    if (hi[i] >= a && lo[i] <= b) {
      if (first < 0) first = i;
      last = i;
    }
  return first < 0 ? std::make_pair(1, 0) : std::make_pair(first, last);
}

}  // namespace

namespace {

// The rays (x/z, y/z) of the vertices of the box cut to near <= z <= far: corners inside that
// slab, and the points where edges cross its two planes. The cut box's image is their hull.
std::vector<Eigen::Vector2d> cut_box_rays(const Box& box, const Pose& T_sensor_world, double near_m, double far_m) {
  static const int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                    {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  std::array<Eigen::Vector3d, 8> c = box_corners(box);
  for (auto& p : c) p = T_sensor_world * p;
  std::vector<Eigen::Vector2d> out;
  auto add = [&](const Eigen::Vector3d& p) { out.emplace_back(p.x() / p.z(), p.y() / p.z()); };
  for (const auto& p : c)
    if (p.z() >= near_m && p.z() <= far_m) add(p);
  for (const auto& e : kEdges) {
    const Eigen::Vector3d &a = c[e[0]], &b = c[e[1]];
    for (double plane : {near_m, far_m})
      if ((a.z() - plane) * (b.z() - plane) < 0) add(a + (b - a) * ((plane - a.z()) / (b.z() - a.z())));
  }
  return out;
}

}  // namespace

cv::Rect box_footprint(const Box& box, const Pose& T_sensor_world, double near_m, double far_m, const DepthView& view) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const auto& r : cut_box_rays(box, T_sensor_world, near_m, far_m)) {
    x0 = std::min(x0, r.x());
    x1 = std::max(x1, r.x());
    y0 = std::min(y0, r.y());
    y1 = std::max(y1, r.y());
  }
  if (!(x0 <= x1)) return {};
  const auto [u0, u1] = overlapping(view.column_min_x, view.column_max_x, x0, x1);
  const auto [v0, v1] = overlapping(view.row_min_y, view.row_max_y, y0, y1);
  if (u0 > u1 || v0 > v1) return {};
  return {u0, v0, u1 - u0 + 1, v1 - v0 + 1};
}

std::vector<cv::Point2f> box_outline(const Box& box, const Pose& T_sensor_world, double near_m, double far_m) {
  std::vector<cv::Point2f> rays, hull;
  for (const auto& r : cut_box_rays(box, T_sensor_world, near_m, far_m))
    if (std::isfinite(r.x()) && std::isfinite(r.y()))
      rays.emplace_back(static_cast<float>(r.x()), static_cast<float>(r.y()));
  if (!rays.empty()) cv::convexHull(rays, hull);
  return hull;
}

std::pair<float, float> outline_x_range(const std::vector<cv::Point2f>& outline, float y0, float y1) {
  float lo = INFINITY, hi = -INFINITY;
  auto take = [&](float x) { lo = std::min(lo, x), hi = std::max(hi, x); };
  for (size_t i = 0; i < outline.size(); ++i) {
    const cv::Point2f a = outline[i], b = outline[(i + 1) % outline.size()];
    if (a.y >= y0 && a.y <= y1) take(a.x);
    for (float y : {y0, y1})  // where the edge crosses the band's borders
      if ((a.y - y) * (b.y - y) < 0) take(a.x + (b.x - a.x) * ((y - a.y) / (b.y - a.y)));
  }
  return {lo, hi};
}

}  // namespace olt
