#include "olt/propagate/propagate.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>

#include "labeler.h"

namespace olt {
using namespace labeling;  // the labeler's parts relabeling shares (labeler.h)
namespace {

// The per-pixel loops are compiled twice, for AVX2 (eight floats at a time) and for any x86-64,
// and the CPU picks at load time. AVX2 alone does not bring FMA, so no multiply and add is fused:
// the answers are the same bits either way.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define OLT_WIDE_VECTORS __attribute__((target_clones("avx2", "default")))
#else
#define OLT_WIDE_VECTORS
#endif

RayTest make_ray_test(const Eigen::Matrix3f& R, const Eigen::Vector3f& origin, const Eigen::Vector3f& half, float near,
                      float far) {
  RayTest t{R, {}, {}, near, far};
  for (int i = 0; i < 3; ++i) t.low[i] = -half[i] - origin[i], t.high[i] = half[i] - origin[i];
  return t;
}

// covered[k] = 1 where the ray of pixel first + k meets the box, for k < n (n <= kRayBlock).
// Without branches, so the compiler tests many rays at a time (four, eight with AVX2); the comparisons are those of
// std::min and std::max, so the answers are those of one ray at a time.
constexpr int kRayBlock = 32;
OLT_WIDE_VECTORS void rays_meeting_box(const RayTest& t, const Eigen::Vector2f* rays, int first, int n,
                                       uint8_t* covered) {
  const float* ray = reinterpret_cast<const float*>(rays + first);
  for (int k = 0; k < n; ++k) {
    const float rx = ray[2 * k], ry = ray[2 * k + 1];
    float enter = t.near, exit = t.far;
    for (int i = 0; i < 3; ++i) {
      const float inv = 1.0f / (t.R(i, 0) * rx + t.R(i, 1) * ry + t.R(i, 2));  // +-inf for a ray parallel to the slab
      float a = t.low[i] * inv, b = t.high[i] * inv;
      const bool along_face = (a != a) | (b != b);  // NaN: the ray lies in the slab's face
      a = along_face ? -INFINITY : a;
      b = along_face ? INFINITY : b;
      const float lo = b < a ? b : a, hi = a < b ? b : a;
      enter = enter < lo ? lo : enter;
      exit = hi < exit ? hi : exit;
    }
    covered[k] = enter <= exit;
  }
}

// The first pixel in [first, last] whose ray meets the box; last + 1 when none does.
int first_covered(const RayTest& t, const Eigen::Vector2f* rays, int first, int last) {
  uint8_t covered[kRayBlock];
  for (int u = first; u <= last; u += kRayBlock) {
    const int n = std::min(kRayBlock, last - u + 1);
    rays_meeting_box(t, rays, u, n, covered);
    for (int k = 0; k < n; ++k)
      if (covered[k]) return u + k;
  }
  return last + 1;
}

// The last pixel in [first, last] whose ray meets the box; first - 1 when none does.
int last_covered(const RayTest& t, const Eigen::Vector2f* rays, int first, int last) {
  uint8_t covered[kRayBlock];
  for (int u = last; u >= first; u -= kRayBlock) {
    const int start = std::max(first, u - kRayBlock + 1), n = u - start + 1;
    rays_meeting_box(t, rays, start, n, covered);
    for (int k = n - 1; k >= 0; --k)
      if (covered[k]) return start + k;
  }
  return first - 1;
}

// The first index in first..last whose ray is not `before` (the rays that are come first), or
// last + 1: std::partition_point, with selects instead of branches, which would mispredict.
template <class Before>
int partition_index(const Eigen::Vector2f* row, int first, int last, Before before) {
  int index = first, n = last - first + 1;
  while (n > 0) {
    const int half = n / 2;
    const bool is_before = before(row[index + half]);
    index = is_before ? index + half + 1 : index;
    n = is_before ? n - half - 1 : half;
  }
  return index;
}

// The pixels of row v that can see the box: those of its rectangle whose ray's x lies within the
// outline's at the row's heights, widened by a margin far beyond the float tests' rounding; the
// whole rectangle's row where the lens folds the row's rays back (x not ascending along it).
// Returns first > last when none can.
std::pair<int, int> row_candidates(const DepthView& view, const std::vector<cv::Point2f>& outline, const cv::Rect& rect,
                                   int v) {
  constexpr float kMargin = 1e-3f;  // in x/z and y/z: 0.5 px at f = 500 px, the rounding ~1e-6
  const int first = rect.x, last = rect.x + rect.width - 1;
  if (outline.empty() || !view.row_x_ascending[v]) return {first, last};
  const std::pair<float, float> range =
      outline_x_range(outline, view.row_min_y[v] - kMargin, view.row_max_y[v] + kMargin);
  const float lo = range.first, hi = range.second;  // not a structured binding: lambdas take them (C++17)
  if (!(lo <= hi)) return {first, first - 1};
  const Eigen::Vector2f* row = view.rays.data() + static_cast<size_t>(v) * view.width;
  const int from = partition_index(row, first, last, [&](const Eigen::Vector2f& r) { return r.x() < lo - kMargin; });
  const int to = partition_index(row, from, last, [&](const Eigen::Vector2f& r) { return r.x() <= hi + kMargin; });
  return {from, to - 1};
}

// What one box's test did to one row.
struct RowHits {
  int labeled = 0, ambiguous = 0, bottom = 0;
  int u_min = INT32_MAX, u_max = -1;  ///< of the pixels it labeled
};

// Pixels first..last of a row against one box, tried after the boxes of higher priority: a pixel
// whose depth point lies inside the box and that no earlier box took takes its class and
// instance; one that an earlier box took already becomes ambiguous (counted once, however many
// boxes hold it). hits counts the boxes holding each pixel, up to 2. Written without branches, in
// the order of operations Eigen evaluates them in, so the compiler handles many pixels at a time
// and the answers are those of one pixel at a time.
OLT_WIDE_VECTORS RowHits label_row(const PointTest& t, const Eigen::Vector2f* rays, const uint16_t* __restrict d,
                                   uint8_t* __restrict hits, uint16_t* __restrict classes,
                                   uint16_t* __restrict instances, uint16_t class_id, uint16_t instance_id, int first,
                                   int last) {
  const float r00 = t.R(0, 0), r01 = t.R(0, 1), r02 = t.R(0, 2), r10 = t.R(1, 0), r11 = t.R(1, 1), r12 = t.R(1, 2),
              r20 = t.R(2, 0), r21 = t.R(2, 1), r22 = t.R(2, 2);
  const float ox = t.origin.x(), oy = t.origin.y(), oz = t.origin.z();
  const float hx = t.half.x(), hy = t.half.y(), hz = t.half.z(), bottom_band = kBottomBand - hz, scale = t.scale;
  static_assert(sizeof(Eigen::Vector2f) == 2 * sizeof(float), "rays are pairs of floats, packed");
  const float* __restrict ray = reinterpret_cast<const float*>(rays);
  int labeled = 0, ambiguous = 0, bottom = 0, u_min = INT32_MAX, u_max = -1;
  for (int u = first; u <= last; ++u) {
    const float rx = ray[2 * u], ry = ray[2 * u + 1], z = static_cast<float>(d[u]) * scale;
    const float x = (r00 * rx + r01 * ry + r02) * z + ox;
    const float y = (r10 * rx + r11 * ry + r12) * z + oy;
    const float h = (r20 * rx + r21 * ry + r22) * z + oz;
    // "not outside", as the test always read: a point of a NaN ray is not taken for outside
    const int in = !(std::abs(x) > hx) & !(std::abs(y) > hy) & !(std::abs(h) > hz) & (classes[u] != kNoDepth);
    const int before = hits[u];
    const int taken = in & (before == 0), all = -taken;  // all: every bit set where taken
    const auto keep = static_cast<uint16_t>(~all);
    ambiguous += in & (before == 1);
    hits[u] = static_cast<uint8_t>(before + (in & (before < 2)));
    classes[u] = static_cast<uint16_t>((classes[u] & keep) | (class_id & ~keep));
    instances[u] = static_cast<uint16_t>((instances[u] & keep) | (instance_id & ~keep));
    labeled += taken;
    bottom += taken & (h < bottom_band);
    u_min = std::min(u_min, (u & all) | (INT32_MAX & ~all));
    u_max = std::max(u_max, (u & all) | ~all);
  }
  return {labeled, ambiguous, bottom, u_min, u_max};
}

}  // namespace

std::vector<LabeledBox> prioritized_boxes(const std::vector<Box>& boxes, const LabelMap& map) {
  std::vector<LabeledBox> out;
  for (const auto& b : boxes) out.push_back({labeling_box(b), map.class_id(b.label), map.instance_id(b.instance)});
  std::sort(out.begin(), out.end(), [](const LabeledBox& a, const LabeledBox& b) {
    if (a.box.priority != b.box.priority) return a.box.priority > b.box.priority;
    const double va = a.box.volume(), vb = b.box.volume();
    return va != vb ? va < vb : a.box.id < b.box.id;
  });
  return out;
}

bool box_in_view(const LabeledBox& box, const SensorCalibration& cal, const DepthView& view,
                 const Pose& T_sensor_world) {
  return !box_footprint(box.box, T_sensor_world, near_limit(cal), cal.max_depth_m, view).empty();
}

std::vector<size_t> boxes_in_view(const std::vector<LabeledBox>& boxes, const SensorCalibration& cal,
                                  const DepthView& view, const Pose& T_world_sensor) {
  const Pose T_sensor_world = T_world_sensor.inverse();
  std::vector<size_t> out;
  for (size_t k = 0; k < boxes.size(); ++k)
    if (box_in_view(boxes[k], cal, view, T_sensor_world)) out.push_back(k);
  return out;
}

namespace labeling {

RowSpans no_pixels(int height) { return RowSpans(static_cast<size_t>(height), {0, -1}); }

std::pair<int, int> candidate_span(const DepthView& view, const Footprint& footprint, int v) {
  return row_candidates(view, footprint.outline, footprint.rect, v);
}

double near_limit(const SensorCalibration& cal) { return std::max(cal.min_depth_m, 1e-3); }

Footprint footprint_of(const Box& box, const Pose& T_sensor_world, double near, double far, const DepthView& view) {
  const cv::Rect rect = box_footprint(box, T_sensor_world, near, far, view);
  return {rect, rect.empty() ? std::vector<cv::Point2f>() : box_outline(box, T_sensor_world, near, far)};
}

// Each box's footprint in a camera at T_world_sensor.
std::vector<Footprint> footprints_of(const std::vector<LabeledBox>& boxes, const SensorCalibration& cal,
                                     const DepthView& view, const Pose& T_world_sensor) {
  const Pose T_sensor_world = T_world_sensor.inverse();
  std::vector<Footprint> footprints;
  for (const auto& b : boxes)
    footprints.push_back(footprint_of(b.box, T_sensor_world, near_limit(cal), cal.max_depth_m, view));
  return footprints;
}

// The run of row v's pixels whose rays meet the box (first > last: none): searched for only where
// its footprint's outline can reach.
std::pair<int, int> covered_run(const DepthView& view, const Footprint& footprint, const RayTest& ray_test, int v) {
  const Eigen::Vector2f* rays = view.rays.data() + static_cast<size_t>(v) * view.width;
  const auto [from, to] = row_candidates(view, footprint.outline, footprint.rect, v);
  const int first = first_covered(ray_test, rays, from, to);
  if (first > to) return {0, -1};
  return {first, std::max(first, last_covered(ray_test, rays, first + 1, to))};
}

// The point test of a box for a camera at T_world_sensor.
PointTest point_test_of(const Box& box, const Pose& T_world_sensor, const SensorCalibration& cal) {
  const Pose T_box_sensor = box.T_world_box.inverse() * T_world_sensor;
  return {T_box_sensor.linear().cast<float>(), T_box_sensor.translation().cast<float>(), (0.5 * box.size).cast<float>(),
          static_cast<float>(1.0 / cal.depth_scale)};
}

// The ray test of the box a point test is of, within the sensor's depth range.
RayTest ray_test_of(const PointTest& t, const SensorCalibration& cal) {
  return make_ray_test(t.R, t.origin, t.half, static_cast<float>(near_limit(cal)), static_cast<float>(cal.max_depth_m));
}

// Labels the pixels of `region` afresh (the others are left as they are) with `boxes` in priority
// order (`footprints`: theirs): each pixel's depth decides whether it can be labeled, then each box
// labels the depth points inside it that no box before it took.
RegionCounts label_region(const cv::Mat& depth, const SensorCalibration& cal, const DepthView& view,
                          const Pose& T_world_sensor, const std::vector<LabeledBox>& boxes,
                          const std::vector<Footprint>& footprints, const RowSpans& region, cv::Mat& class_ids,
                          cv::Mat& instance_ids) {
  const int width = depth.cols;
  RegionCounts out{0, 0, 0, std::vector<BoxInFrame>(boxes.size())};
  // Depth units of the range limits: a pixel is valid when its raw value lies between them.
  const double near = near_limit(cal), far = cal.max_depth_m;
  // Raw values are whole numbers, so the limits are too: the first at or above the near one, the
  // last at or below the far one.
  const double lo_units = std::max(1.0, near * cal.depth_scale), hi_units = far * cal.depth_scale;
  const int lo = static_cast<int>(std::min(std::ceil(lo_units), 65536.0));
  const int hi = static_cast<int>(hi_units >= 65535.0 ? 65535.0
                                  : hi_units >= 0     ? std::floor(hi_units)
                                                      : -1.0);  // NaN: none
  for (int v = 0; v < depth.rows; ++v) {
    const auto [from, to] = region[static_cast<size_t>(v)];
    const uint16_t* d = depth.ptr<uint16_t>(v);
    uint16_t* classes = class_ids.ptr<uint16_t>(v);
    uint16_t* instances = instance_ids.ptr<uint16_t>(v);
    int valid_pixels = 0;
    for (int u = from; u <= to; ++u) {
      const int valid = (d[u] >= lo) & (d[u] <= hi);
      classes[u] = instances[u] = valid ? kUnlabeled : kNoDepth;
      valid_pixels += valid;
    }
    out.valid_pixels += valid_pixels;
  }
  // How many boxes hold each pixel, up to 2: the region's rows only (after an edit, a few).
  int rows_from = depth.rows, rows_to = -1;
  for (int v = 0; v < depth.rows; ++v)
    if (!empty_span(region[static_cast<size_t>(v)])) rows_from = std::min(rows_from, v), rows_to = v;
  std::vector<uint8_t> hits(static_cast<size_t>(width) * static_cast<size_t>(std::max(0, rows_to - rows_from + 1)), 0);
  for (size_t k = 0; k < boxes.size(); ++k) {
    const Footprint& footprint = footprints[k];
    const cv::Rect& rect = footprint.rect;
    if (rect.empty()) continue;
    BoxInFrame& seen = out.boxes[k];
    const PointTest test = point_test_of(boxes[k].box, T_world_sensor, cal);
    const RayTest ray_test = ray_test_of(test, cal);
    int u_min = width, v_min = depth.rows, u_max = -1, v_max = -1;
    for (int v = rect.y; v < rect.y + rect.height; ++v) {
      const auto [region_from, region_to] = region[static_cast<size_t>(v)];
      if (region_to < rect.x || region_from > rect.x + rect.width - 1) continue;  // also where the row has none
      const Eigen::Vector2f* rays = view.rays.data() + static_cast<size_t>(v) * width;
      // The pixels of a row whose rays meet a convex box are one run: its ends, found as on the
      // whole image, then cut to the region; counted as covered, their depth points tested.
      const auto [run_first, run_last] = covered_run(view, footprint, ray_test, v);
      const int first = std::max(run_first, region_from), last = std::min(run_last, region_to);
      if (first > last) continue;
      seen.covered_pixels += last - first + 1;
      const uint16_t* d = depth.ptr<uint16_t>(v);
      uint16_t* classes = class_ids.ptr<uint16_t>(v);
      uint16_t* instances = instance_ids.ptr<uint16_t>(v);
      uint8_t* row_hits = hits.data() + static_cast<size_t>(v - rows_from) * width;
      const RowHits row =
          label_row(test, rays, d, row_hits, classes, instances, boxes[k].class_id, boxes[k].instance_id, first, last);
      out.ambiguous_pixels += row.ambiguous;
      if (row.labeled == 0) continue;
      seen.labeled_pixels += row.labeled;
      seen.bottom_pixels += row.bottom;
      out.labeled_pixels += row.labeled;
      u_min = std::min(u_min, row.u_min), u_max = std::max(u_max, row.u_max);
      v_min = std::min(v_min, v), v_max = std::max(v_max, v);
    }
    if (u_max >= 0) seen.bbox = cv::Rect(u_min, v_min, u_max - u_min + 1, v_max - v_min + 1);
  }
  return out;
}

// label_row's operations in the same order (see labeler.h).
bool holds(const PointTest& t, const Eigen::Vector2f& ray, uint16_t raw) {
  const float rx = ray.x(), ry = ray.y(), z = static_cast<float>(raw) * t.scale;
  const float x = (t.R(0, 0) * rx + t.R(0, 1) * ry + t.R(0, 2)) * z + t.origin.x();
  const float y = (t.R(1, 0) * rx + t.R(1, 1) * ry + t.R(1, 2)) * z + t.origin.y();
  const float h = (t.R(2, 0) * rx + t.R(2, 1) * ry + t.R(2, 2)) * z + t.origin.z();
  return !(std::abs(x) > t.half.x()) & !(std::abs(y) > t.half.y()) & !(std::abs(h) > t.half.z());
}

}  // namespace labeling

FrameLabels label_depth_image(const cv::Mat& depth, const SensorCalibration& cal, const DepthView& view,
                              const Pose& T_world_sensor, const std::vector<LabeledBox>& boxes) {
  FrameLabels out{
      cv::Mat(depth.rows, depth.cols, CV_16UC1), cv::Mat(depth.rows, depth.cols, CV_16UC1), 0, 0, 0, {}, {}, {}};
  const RowSpans everything(static_cast<size_t>(depth.rows), {0, depth.cols - 1});
  out.footprints = footprints_of(boxes, cal, view, T_world_sensor);
  RegionCounts counts = label_region(depth, cal, view, T_world_sensor, boxes, out.footprints, everything, out.class_ids,
                                     out.instance_ids);
  out.valid_pixels = counts.valid_pixels;
  out.labeled_pixels = counts.labeled_pixels;
  out.ambiguous_pixels = counts.ambiguous_pixels;
  out.boxes = std::move(counts.boxes);
  return out;
}

bool color_is_depth_camera(const SensorCalibration& cal) {
  const Intrinsics &a = cal.depth, &b = cal.color;
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy &&
         a.distortion == b.distortion && cal.T_color_depth.isApprox(Pose::Identity(), 1e-12);
}

ColorLabels label_color_image(const FrameLabels& labels, const cv::Mat& depth, const SensorCalibration& cal,
                              const DepthView& view, int fill_px, double fill_tolerance_m) {
  if (color_is_depth_camera(cal)) return {labels.class_ids.clone(), labels.instance_ids.clone()};
  const int width = cal.color.width, height = cal.color.height;
  ColorLabels out{cv::Mat(height, width, CV_16UC1, cv::Scalar(kNoDepth)),
                  cv::Mat(height, width, CV_16UC1, cv::Scalar(kNoDepth))};
  cv::Mat nearest(height, width, CV_32F, cv::Scalar(INFINITY));  // z in the colour camera
  const double scale = 1.0 / cal.depth_scale;
  for (int v = 0; v < depth.rows; ++v) {
    const uint16_t* d = depth.ptr<uint16_t>(v);
    const uint16_t* classes = labels.class_ids.ptr<uint16_t>(v);
    const uint16_t* instances = labels.instance_ids.ptr<uint16_t>(v);
    for (int u = 0; u < depth.cols; ++u) {
      if (classes[u] == kNoDepth) continue;
      const double z = d[u] * scale;
      const Eigen::Vector2f& r = view.rays[static_cast<size_t>(v) * depth.cols + u];
      const Eigen::Vector3d p = cal.T_color_depth * Eigen::Vector3d(r.x() * z, r.y() * z, z);
      Eigen::Vector2d px;
      if (!project(cal.color, p, &px)) continue;
      const int cu = static_cast<int>(std::lround(px.x())), cv_ = static_cast<int>(std::lround(px.y()));
      if (cu < 0 || cv_ < 0 || cu >= width || cv_ >= height) continue;
      float& front = nearest.at<float>(cv_, cu);
      if (p.z() >= front) continue;
      front = static_cast<float>(p.z());
      out.class_ids.at<uint16_t>(cv_, cu) = classes[u];
      out.instance_ids.at<uint16_t>(cv_, cu) = instances[u];
    }
  }
  if (fill_px <= 0) return out;
  const ColorLabels reached{out.class_ids.clone(), out.instance_ids.clone()};
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      if (std::isfinite(nearest.at<float>(v, u))) continue;
      const int v0 = std::max(0, v - fill_px), v1 = std::min(height - 1, v + fill_px);
      const int u0 = std::max(0, u - fill_px), u1 = std::min(width - 1, u + fill_px);
      float front = INFINITY;
      for (int y = v0; y <= v1; ++y)
        for (int x = u0; x <= u1; ++x) front = std::min(front, nearest.at<float>(y, x));
      if (!std::isfinite(front)) continue;
      int best = INT32_MAX, bu = -1, bv = -1;
      for (int y = v0; y <= v1; ++y)
        for (int x = u0; x <= u1; ++x) {
          const int distance = (x - u) * (x - u) + (y - v) * (y - v);
          if (nearest.at<float>(y, x) <= front + fill_tolerance_m && distance < best) best = distance, bu = x, bv = y;
        }
      out.class_ids.at<uint16_t>(v, u) = reached.class_ids.at<uint16_t>(bv, bu);
      out.instance_ids.at<uint16_t>(v, u) = reached.instance_ids.at<uint16_t>(bv, bu);
    }
  return out;
}

LabeledCloud labeled_cloud(const FrameLabels& labels, const cv::Mat& depth, const cv::Mat& color_bgr,
                           const SensorCalibration& cal, const DepthView& view) {
  LabeledCloud cloud;
  cloud.reserve(static_cast<size_t>(labels.valid_pixels));
  const double scale = 1.0 / cal.depth_scale;
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      const uint16_t class_id = labels.class_ids.at<uint16_t>(v, u);
      if (class_id == kNoDepth) continue;
      const double z = depth.at<uint16_t>(v, u) * scale;
      const Eigen::Vector2f& r = view.rays[static_cast<size_t>(v) * depth.cols + u];
      const Eigen::Vector3d p(r.x() * z, r.y() * z, z);
      LabeledPoint q;
      q.x = static_cast<float>(p.x()), q.y = static_cast<float>(p.y()), q.z = static_cast<float>(p.z());
      q.class_id = class_id;
      q.instance_id = labels.instance_ids.at<uint16_t>(v, u);
      Eigen::Vector2d px;
      if (!color_bgr.empty() && project(cal.color, cal.T_color_depth * p, &px)) {
        const int cu = static_cast<int>(std::lround(px.x())), cv_ = static_cast<int>(std::lround(px.y()));
        if (cu >= 0 && cv_ >= 0 && cu < color_bgr.cols && cv_ < color_bgr.rows) {
          const cv::Vec3b& c = color_bgr.at<cv::Vec3b>(cv_, cu);
          q.r = c[2], q.g = c[1], q.b = c[0];
        }
      }
      cloud.push_back(q);
    }
  return cloud;
}

namespace {

// A box's 12 edges in the depth image, clipped to the space in front of the camera.
std::vector<std::pair<cv::Point, cv::Point>> outline_of(const Box& box, const SensorCalibration& cal,
                                                        const Pose& T_sensor_world) {
  static const int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                    {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  const auto corners = box_corners(box);
  std::vector<std::pair<cv::Point, cv::Point>> edges;
  for (const auto& e : kEdges) {
    Eigen::Vector3d a = T_sensor_world * corners[e[0]], b = T_sensor_world * corners[e[1]];
    constexpr double kNear = 0.05;
    if (a.z() < kNear && b.z() < kNear) continue;
    if (a.z() < kNear) a = b + (a - b) * ((b.z() - kNear) / (b.z() - a.z()));
    if (b.z() < kNear) b = a + (b - a) * ((a.z() - kNear) / (a.z() - b.z()));
    Eigen::Vector2d pa, pb;
    project(cal.depth, a, &pa);
    project(cal.depth, b, &pb);
    edges.emplace_back(cv::Point2d(pa.x(), pa.y()), cv::Point2d(pb.x(), pb.y()));
  }
  return edges;
}

// The rows an antialiased line of an outline can touch (a row more each side of its ends; far ends
// are saturated to int's range), within an image of `rows` rows: [first, last], empty when first > last.
std::pair<int, int> rows_touched(const std::pair<cv::Point, cv::Point>& edge, int rows) {
  const auto& [a, b] = edge;
  return {static_cast<int>(std::max<int64_t>(0, int64_t{std::min(a.y, b.y)} - 2)),
          static_cast<int>(std::min<int64_t>(rows - 1, int64_t{std::max(a.y, b.y)} + 2))};
}

// The same outline, drawn in the same colour.
bool same_outline(const LabeledBox& a, const LabeledBox& b) {
  return a.class_id == b.class_id && a.box.size == b.box.size &&
         a.box.T_world_box.matrix() == b.box.T_world_box.matrix();
}

}  // namespace

cv::Mat render_overlay(const cv::Mat& color_bgr, const cv::Mat& depth, const FrameLabels& labels, const LabelMap& map,
                       const std::vector<LabeledBox>& boxes, const SensorCalibration& cal, const Pose& T_world_sensor,
                       const std::vector<bool>& rows) {
  if (!rows.empty() && rows.size() != static_cast<size_t>(depth.rows))
    throw std::invalid_argument("render_overlay: expected a flag per row");
  const auto drawn = [&](int v) { return rows.empty() || rows[static_cast<size_t>(v)]; };
  cv::Mat overlay;  // an image of its own: the colour image may be shared
  cv::Mat under;    // what the labels are blended over, where not the overlay itself
  if (color_bgr.size() == depth.size() && !rows.empty()) {
    // Blended from the colour image as it is read (no copy of its rows first); the rows not drawn
    // left undefined (the outlines' antialiasing blends into them: nothing reads them, only the rows
    // drawn are encoded).
    overlay.create(color_bgr.size(), color_bgr.type());
    under = color_bgr;
  } else if (color_bgr.size() == depth.size()) {
    overlay = color_bgr.clone();
  } else if (!color_bgr.empty()) {
    cv::resize(color_bgr, overlay, depth.size(), 0, 0, cv::INTER_AREA);
  } else {
    cv::Mat grey;
    depth.convertTo(grey, CV_8U, 255.0 / (cal.max_depth_m * cal.depth_scale));
    cv::cvtColor(grey, overlay, cv::COLOR_GRAY2BGR);
  }
  uint16_t top = 0;  // the highest class id: the lookup below is as long as that, not 65,536
  for (const auto& c : map.classes) top = std::max(top, c.id);
  std::vector<const LabelClass*> class_of(top + size_t{1}, nullptr);  // by class id
  for (const auto& c : map.classes) class_of[c.id] = &c;
  for (int v = 0; v < overlay.rows; ++v) {
    if (!drawn(v)) continue;
    const uint16_t* ids = labels.class_ids.ptr<uint16_t>(v);
    cv::Vec3b* row = overlay.ptr<cv::Vec3b>(v);
    const cv::Vec3b* from = under.empty() ? row : under.ptr<cv::Vec3b>(v);
    for (int u = 0; u < overlay.cols; ++u) {
      const cv::Vec3b px = from[u];
      if (ids[u] == kNoDepth) {
        row[u] = cv::Vec3b(px[0] / 3, px[1] / 3, px[2] / 3);  // darken: no depth, no label possible
      } else if (const LabelClass* c = ids[u] <= top ? class_of[ids[u]] : nullptr; c && ids[u] != kUnlabeled) {
        row[u] = cv::Vec3b((px[0] + c->color[2]) / 2, (px[1] + c->color[1]) / 2, (px[2] + c->color[0]) / 2);
      } else {
        row[u] = px;
      }
    }
  }
  // Box outlines, in order (a line blends into the lines drawn before it).
  const Pose T_sensor_world = T_world_sensor.inverse();
  for (const auto& lb : boxes) {
    const auto color = class_color(lb.class_id);
    for (const auto& edge : outline_of(lb.box, cal, T_sensor_world)) {
      const auto [first, last] = rows_touched(edge, overlay.rows);
      bool needed = rows.empty();  // a line in no row drawn changes none
      for (int v = first; v <= last && !needed; ++v) needed = drawn(v);
      if (needed) cv::line(overlay, edge.first, edge.second, cv::Scalar(color[2], color[1], color[0]), 1, cv::LINE_AA);
    }
  }
  return overlay;
}

std::vector<bool> overlay_rows_changed(std::vector<bool> classes_differ, const std::vector<LabeledBox>& boxes,
                                       const std::vector<LabeledBox>& previous_boxes, const SensorCalibration& cal,
                                       const Pose& T_world_sensor) {
  std::vector<bool> changed = std::move(classes_differ);
  const int rows = static_cast<int>(changed.size());
  // A pixel's lines are those of the boxes at the same place in both orders, drawn in the same
  // order, unless a box that differs at its place (or has none in the other order) draws there.
  const Pose T_sensor_world = T_world_sensor.inverse();
  const auto mark = [&](const LabeledBox& lb) {
    for (const auto& edge : outline_of(lb.box, cal, T_sensor_world)) {
      const auto [first, last] = rows_touched(edge, rows);
      for (int v = first; v <= last; ++v) changed[static_cast<size_t>(v)] = true;
    }
  };
  for (size_t k = 0; k < std::max(boxes.size(), previous_boxes.size()); ++k) {
    const bool both = k < boxes.size() && k < previous_boxes.size();
    if (both && same_outline(boxes[k], previous_boxes[k])) continue;
    if (k < boxes.size()) mark(boxes[k]);
    if (k < previous_boxes.size()) mark(previous_boxes[k]);
  }
  return changed;
}

}  // namespace olt
