#include "olt/reconstruct/preview.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <tuple>

namespace olt {
namespace {

const cv::Scalar kBackground(38, 38, 38), kText(225, 225, 225), kShadow(0, 0, 0);
const cv::Scalar kRed(40, 40, 235), kGreen(40, 200, 40), kBlue(255, 120, 30);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

double font_scale(int size_px) { return std::clamp(size_px / 1300.0, 0.36, 0.8); }

// Text with a dark outline, readable on points of any colour.
void outlined_text(cv::Mat& image, const std::string& text, cv::Point at, double scale, const cv::Scalar& color) {
  cv::putText(image, text, at, kFont, scale, kShadow, 3, cv::LINE_AA);
  cv::putText(image, text, at, kFont, scale, color, 1, cv::LINE_AA);
}

cv::Size text_size(const std::string& text, double scale) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, 1, &baseline);
}

// "1.5" for k = 3, step 0.5: from the integer multiple, so no "1.4999" and no "-0".
std::string metres(long k, double step) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", step < 1 ? 1 : 0, k == 0 ? 0.0 : k * step);
  return text;
}

// A grid line lightens dark pixels and darkens light ones, so it shows on the floor and on the
// background alike.
void grid_pixel(cv::Vec3b& p) {
  const int luma = (p[0] + 2 * p[1] + p[2]) / 4;
  for (int c = 0; c < 3; ++c) p[c] = static_cast<uchar>(luma < 128 ? (p[c] + 255) / 2 : p[c] / 2);
}

// The indices k of the grid lines k * step inside [lo, hi].
std::pair<long, long> grid_range(double lo, double hi, double step) {
  return {static_cast<long>(std::ceil(lo / step - 1e-9)), static_cast<long>(std::floor(hi / step + 1e-9))};
}

// A point with a coordinate that is not a number is in no region (it has no place to be drawn).
bool inside(const ColoredPoint& q, const Region& region) {
  const Eigen::Vector3d p(q.x, q.y, q.z);
  return p.allFinite() && (p.array() >= region.lo.array()).all() && (p.array() <= region.hi.array()).all();
}

// The points of `cloud` in `region`, in the cloud's order: looked for among those whose x is in it,
// marked, then read in order. None where the region holds most of the points (a scan is faster).
std::optional<std::vector<uint32_t>> points_inside(const ColoredCloud& cloud, const Region& region,
                                                   const PointsByX& order) {
  const auto x_of = [&](uint32_t i) { return static_cast<double>(cloud[i].x); };
  const auto first = std::lower_bound(order.by_x.begin(), order.by_x.end(), region.lo.x(),
                                      [&](uint32_t i, double lo) { return x_of(i) < lo; });
  const auto last =
      std::upper_bound(first, order.by_x.end(), region.hi.x(), [&](double hi, uint32_t i) { return hi < x_of(i); });
  if (static_cast<size_t>(last - first) > cloud.size() / 2) return std::nullopt;
  std::vector<uint64_t> marked((cloud.size() + 63) / 64, 0);
  std::for_each(first, last, [&](uint32_t i) {
    if (inside(cloud[i], region)) marked[i / 64] |= uint64_t{1} << (i % 64);
  });
  std::vector<uint32_t> points;
  for (size_t w = 0; w < marked.size(); ++w)
    for (uint64_t bits = marked[w]; bits; bits &= bits - 1)
      points.push_back(static_cast<uint32_t>(w * 64 + static_cast<size_t>(__builtin_ctzll(bits))));
  return points;
}

// The points in the region, each a square `point_size_m` wide (a pixel at least), the nearest
// winning (the first of equals): all of them looked at, or only those `points` lists.
void draw_points(cv::Mat& canvas, const OrthoView& view, const ColoredCloud& cloud, const Region& region,
                 double point_size_m, const std::vector<uint32_t>* points) {
  const cv::Rect& plot = view.plot;
  cv::Mat nearest(plot.size(), CV_64F, cv::Scalar(std::numeric_limits<double>::infinity()));
  const int splat = std::max(1, static_cast<int>(std::ceil(point_size_m * view.px_per_m)));
  const auto draw = [&](const ColoredPoint& q) {
    const Eigen::Vector3d p(q.x, q.y, q.z);
    const cv::Point centre = view.pixel(p) - plot.tl() - cv::Point(splat / 2, splat / 2);
    const double depth = view.depth(p);
    for (int v = std::max(0, centre.y); v < std::min(plot.height, centre.y + splat); ++v)
      for (int u = std::max(0, centre.x); u < std::min(plot.width, centre.x + splat); ++u) {
        if (depth >= nearest.at<double>(v, u)) continue;
        nearest.at<double>(v, u) = depth;
        canvas.at<cv::Vec3b>(plot.y + v, plot.x + u) = cv::Vec3b(q.b, q.g, q.r);
      }
  };
  if (points) {
    for (uint32_t i : *points) draw(cloud[i]);
    return;
  }
  for (const auto& q : cloud)
    if (inside(q, region)) draw(q);
}

// Grid lines every step inside the plot, their values in the margins left of and under it.
void draw_grid(cv::Mat& canvas, const OrthoView& view, const PreviewLayout& layout, double scale) {
  const cv::Rect& plot = view.plot;
  const double step = layout.grid_step_m;
  const int a = view.axis_v;
  auto [x0, x1] = grid_range(layout.region.lo.x(), layout.region.hi.x(), step);
  int free_from = 0;  // labels under the plot do not overlap: the first column still free
  for (long k = x0; k <= x1; ++k) {
    const int u = view.pixel(Eigen::Vector3d(k * step, 0, 0)).x;
    if (u < plot.x || u >= plot.br().x) continue;
    for (int v = plot.y; v < plot.br().y; ++v) grid_pixel(canvas.at<cv::Vec3b>(v, u));
    const std::string text = metres(k, step);
    const cv::Size size = text_size(text, scale);
    const int left = u - size.width / 2;
    if (left < free_from) continue;
    cv::putText(canvas, text, {left, plot.br().y + size.height + 5}, kFont, scale, kText, 1, cv::LINE_AA);
    free_from = left + size.width + 6;
  }
  auto [y0, y1] = grid_range(layout.region.lo[a], layout.region.hi[a], step);
  int free_above = std::numeric_limits<int>::max();  // labels beside the plot, drawn bottom up
  for (long k = y0; k <= y1; ++k) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    p[a] = k * step;
    const int v = view.pixel(p).y;
    if (v < plot.y || v >= plot.br().y) continue;
    for (int u = plot.x; u < plot.br().x; ++u) grid_pixel(canvas.at<cv::Vec3b>(v, u));
    const std::string text = metres(k, step);
    const cv::Size size = text_size(text, scale);
    const int baseline = v + size.height / 2;
    if (baseline > free_above) continue;
    cv::putText(canvas, text, {plot.x - size.width - 5, baseline}, kFont, scale, kText, 1, cv::LINE_AA);
    free_above = baseline - size.height - 4;
  }
}

// The axes from the origin, 1 m long (a grid step where steps are longer); the one pointing at the
// viewer a ringed dot, the one pointing away a ringed cross.
void draw_axes(cv::Mat& plot_image, const OrthoView& view, double length_m, double scale) {
  const cv::Point o = view.pixel(Eigen::Vector3d::Zero()) - view.plot.tl();
  const Eigen::Vector3d up = view.axis_v == 1 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  const cv::Scalar up_color = view.axis_v == 1 ? kGreen : kBlue, through_color = view.axis_v == 1 ? kBlue : kGreen;
  const std::pair<Eigen::Vector3d, std::pair<cv::Scalar, const char*>> axes[] = {
      {Eigen::Vector3d::UnitX(), {kRed, "x"}}, {up, {up_color, view.axis_v == 1 ? "y" : "z"}}};
  for (const auto& [direction, style] : axes) {
    const cv::Point tip = view.pixel(length_m * direction) - view.plot.tl();
    cv::arrowedLine(plot_image, o, tip, style.first, 2, cv::LINE_8, 0, 12 / std::max(12.0, length_m * view.px_per_m));
    const cv::Point at = direction.x() > 0 ? tip + cv::Point(6, 5) : tip + cv::Point(-4, -8);
    outlined_text(plot_image, style.second, at, scale * 1.3, style.first);
  }
  const int r = 7;
  cv::circle(plot_image, o, r, {255, 255, 255}, 1, cv::LINE_8);
  if (view.axis_v == 1) {
    cv::circle(plot_image, o, 2, through_color, -1, cv::LINE_8);  // z: out of the picture
  } else {
    cv::line(plot_image, o + cv::Point(-4, -4), o + cv::Point(4, 4), through_color, 1, cv::LINE_8);  // y: into it
    cv::line(plot_image, o + cv::Point(-4, 4), o + cv::Point(4, -4), through_color, 1, cv::LINE_8);
  }
  outlined_text(plot_image, view.axis_v == 1 ? "z" : "y", o + cv::Point(-r - 12, r + 12), scale * 1.3, through_color);
}

// One grid step as a bar in the plot's lower right corner, its length written above it.
void draw_scale_bar(cv::Mat& canvas, const OrthoView& view, double step, double scale) {
  const int length = static_cast<int>(std::lround(step * view.px_per_m));
  const cv::Point end(view.plot.br().x - 10, view.plot.br().y - 10), start = end - cv::Point(length, 0);
  cv::rectangle(canvas, start - cv::Point(1, 3), end + cv::Point(1, 3), kShadow, -1);
  cv::rectangle(canvas, start - cv::Point(0, 2), end + cv::Point(0, 2), {255, 255, 255}, -1);
  const std::string text = metres(1, step) + " m";
  outlined_text(canvas, text, {end.x - text_size(text, scale).width, start.y - 8}, scale, {255, 255, 255});
}

}  // namespace

Eigen::Vector2d OrthoView::project(const Eigen::Vector3d& p) const {
  return {origin_px.x() + p.x() * px_per_m, origin_px.y() - p[axis_v] * px_per_m};
}

cv::Point OrthoView::pixel(const Eigen::Vector3d& p) const {
  const Eigen::Vector2d uv = project(p);
  return {static_cast<int>(std::floor(uv.x())), static_cast<int>(std::floor(uv.y()))};
}

Region scene_region(const ColoredCloud& cloud, double pad_m) {
  Region r;
  if (!cloud.empty()) {
    std::vector<float> values(cloud.size());
    for (int axis = 0; axis < 3; ++axis) {
      for (size_t i = 0; i < cloud.size(); ++i)
        values[i] = axis == 0 ? cloud[i].x : axis == 1 ? cloud[i].y : cloud[i].z;
      const size_t low = values.size() / 500, high = values.size() - 1 - low;
      std::nth_element(values.begin(), values.begin() + low, values.end());
      r.lo[axis] = values[low];
      std::nth_element(values.begin(), values.begin() + high, values.end());
      r.hi[axis] = values[high];
    }
  }
  r.lo = r.lo.cwiseMin(Eigen::Vector3d::Zero()).array() - pad_m;
  r.hi = r.hi.cwiseMax(Eigen::Vector3d::Zero()).array() + pad_m;
  return r;
}

PreviewLayout preview_layout(const Region& region, int size_px, int min_grid_px) {
  PreviewLayout layout;
  layout.region = region;
  layout.canvas = cv::Size(2 * size_px, size_px);
  const int top = std::max(18, size_px / 20), left = std::max(26, size_px * 3 / 40),
            bottom = std::max(14, size_px / 25), right = std::max(4, size_px / 60);
  const cv::Size plot(size_px - left - right, size_px - top - bottom);
  const Eigen::Vector3d extent = (region.hi - region.lo).cwiseMax(1e-3);
  const double s = std::min({plot.width / extent.x(), plot.height / extent.y(), plot.height / extent.z()});
  for (int i = 0; i < 2; ++i) {
    OrthoView& view = layout.views[i];
    view.axis_v = i == 0 ? 1 : 2;
    view.panel = cv::Rect(i * size_px, 0, size_px, size_px);
    view.plot = cv::Rect(view.panel.x + left, top, plot.width, plot.height);
    view.px_per_m = s;
    // The region centred in the plot.
    const int a = view.axis_v;
    view.origin_px = {view.plot.x + (plot.width - extent.x() * s) / 2 - region.lo.x() * s,
                      view.plot.y + plot.height - (plot.height - extent[a] * s) / 2 + region.lo[a] * s};
  }
  layout.grid_step_m = 10;
  for (double step : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0})
    if (step * s >= min_grid_px) {
      layout.grid_step_m = step;
      break;
    }
  return layout;
}

BoxOutline box_outline(const OrthoView& view, const PreviewBox& box) {
  BoxOutline outline;
  for (size_t i = 0; i < 8; ++i) outline.corners[i] = view.project(box.corners[i]);
  const Eigen::Vector2d top = *std::min_element(outline.corners.begin(), outline.corners.end(),
                                                [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
                                                  return std::tie(a.y(), a.x()) < std::tie(b.y(), b.x());
                                                });
  outline.text_at = top + Eigen::Vector2d(3, -5);
  return outline;
}

double name_font_px(const PreviewLayout& layout) { return std::round(30 * font_scale(layout.canvas.height)); }

bool box_shows(const PreviewBox& box, const PreviewLayout& layout) {
  const double font_px = name_font_px(layout);
  // Whether [lo, hi] meets the plot, both in canvas pixels.
  const auto meets = [](const cv::Rect& plot, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
    return lo.x() < plot.br().x && hi.x() > plot.x && lo.y() < plot.br().y && hi.y() > plot.y;
  };
  for (const OrthoView& view : layout.views) {
    const BoxOutline outline = box_outline(view, box);
    // The edges lie in their corners' hull, widened by the line's width (and a pixel to spare).
    Eigen::Vector2d lo = outline.corners[0], hi = outline.corners[0];
    for (const auto& c : outline.corners) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
    const double grow = box.thickness_px + 1;
    if (meets(view.plot, (lo.array() - grow).matrix(), (hi.array() + grow).matrix())) return true;
    if (box.text.empty()) continue;
    // The name: at most a font size wide per character, a font size and a half high, its outline around.
    const Eigen::Vector2d text_lo = outline.text_at - Eigen::Vector2d(3, font_px + 3);
    const Eigen::Vector2d text_hi =
        outline.text_at + Eigen::Vector2d(font_px * static_cast<double>(box.text.size()) + 3, font_px / 2 + 3);
    if (meets(view.plot, text_lo, text_hi)) return true;
  }
  return false;
}

PointsByX points_by_x(const ColoredCloud& cloud) {
  PointsByX order;
  if (cloud.size() > std::numeric_limits<uint32_t>::max()) return order;  // for no cloud: pictures scan it
  order.cloud_size = cloud.size();
  for (size_t i = 0; i < cloud.size(); ++i)
    if (!std::isnan(cloud[i].x)) order.by_x.push_back(static_cast<uint32_t>(i));  // the others are in no region
  std::sort(order.by_x.begin(), order.by_x.end(), [&](uint32_t a, uint32_t b) { return cloud[a].x < cloud[b].x; });
  return order;
}

cv::Mat render_preview(const ColoredCloud& cloud, const PreviewLayout& layout, const PreviewStyle& style,
                       const PointsByX* by_x) {
  cv::Mat canvas(layout.canvas, CV_8UC3, kBackground);
  const double scale = font_scale(layout.canvas.height);
  std::optional<std::vector<uint32_t>> points;
  if (by_x && by_x->cloud_size == cloud.size() && !cloud.empty()) points = points_inside(cloud, layout.region, *by_x);
  for (const OrthoView& view : layout.views) {
    cv::rectangle(canvas, view.plot, {60, 60, 60}, -1);
    draw_points(canvas, view, cloud, layout.region, style.point_size_m, points ? &*points : nullptr);
    draw_grid(canvas, view, layout, scale);
    cv::Mat plot_image = canvas(view.plot);  // drawing clipped to the plot
    if (style.axes) draw_axes(plot_image, view, std::max(1.0, layout.grid_step_m), scale);
    draw_scale_bar(canvas, view, layout.grid_step_m, scale);
    const std::string title = style.title + (view.axis_v == 1 ? "top (x right, y up)" : "front (x right, z up)") +
                              ", grid " + metres(1, layout.grid_step_m) + " m";
    cv::putText(canvas, title, {view.plot.x, view.plot.y - 7}, kFont, scale * 1.15, kText, 1, cv::LINE_AA);
  }
  return canvas;
}

}  // namespace olt
