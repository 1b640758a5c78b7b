#pragma once
// Which boxes a depth camera can see, and where: a box is clipped to the sensor's depth range and
// its clipped corners' rays bound the pixels that can hold its points. Exact for any lens the ray
// table describes (distortion included) and conservative: a pixel outside the footprint can never
// be labeled by the box. It decides both what a frame's labels depend on (the cache key) and which
// pixels the labeler tests.
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/camera.h"

namespace olt {

/// A depth camera's pixel rays (normalised x/z, y/z, row-major) and, per column and per row, the
/// range of their x and y.
struct DepthView {
  int width = 0, height = 0;
  std::vector<Eigen::Vector2f> rays;
  std::vector<float> column_min_x, column_max_x;  ///< per column u
  std::vector<float> row_min_y, row_max_y;        ///< per row v
  std::vector<uint8_t> row_x_ascending;           ///< per row v: 1 when its rays' x never decreases along it
};

DepthView make_depth_view(const Intrinsics& depth_camera);

/// make_depth_view, made once per process for each camera: `olt watch` relabels in one process, and
/// a 640x480 camera's rays take ~80 ms to undistort. Keeps the last 16 cameras; thread-safe.
std::shared_ptr<const DepthView> shared_depth_view(const Intrinsics& depth_camera);

/// The pixel rectangle that can see `box` between `near_m` and `far_m` along the optical axis;
/// empty when the box is out of view within that range.
cv::Rect box_footprint(const Box& box, const Pose& T_sensor_world, double near_m, double far_m, const DepthView& view);

/// The image of `box` cut to near_m <= z <= far_m, in ray space (x/z, y/z): a convex polygon, its
/// vertices in order; empty when no part of the box lies within that range. Every ray that meets
/// the box within the range lies inside it.
std::vector<cv::Point2f> box_outline(const Box& box, const Pose& T_sensor_world, double near_m, double far_m);

/// The smallest and largest x of `outline` where y0 <= y <= y1; lo > hi when it does not reach there.
std::pair<float, float> outline_x_range(const std::vector<cv::Point2f>& outline, float y0, float y1);

}  // namespace olt
