#pragma once
// The labeler's parts that relabeling in place shares with it (private to src/propagate): a box's
// point and ray tests, where it can label in a camera, and labeling a region of an image afresh.
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "olt/propagate/propagate.h"

namespace olt::labeling {

/// The nearest depth the labeler considers: the sensor's minimum, kept off zero for the projections.
double near_limit(const SensorCalibration& cal);

/// A box's test of depth points, in the box frame: a pixel's point is direction(ray) * z + origin,
/// with direction(ray) = R.col(0) * ray.x + R.col(1) * ray.y + R.col(2) and z its depth in metres.
struct PointTest {
  Eigen::Matrix3f R;
  Eigen::Vector3f origin, half;
  float scale;  ///< metres per depth unit
};

/// Whether a pixel's ray meets a box within the depth range, in the box frame: the ray is
/// origin + z * direction(ray), direction(ray) = R.col(0) * ray.x + R.col(1) * ray.y + R.col(2), and
/// meets the box for z between the slabs' entry and exit.
struct RayTest {
  Eigen::Matrix3f R;
  float low[3], high[3];  ///< the slabs' faces relative to the origin: -half - origin, half - origin
  float near, far;
};

/// The point test of a box for a camera at T_world_sensor, and its ray test within the sensor's
/// depth range.
PointTest point_test_of(const Box& box, const Pose& T_world_sensor, const SensorCalibration& cal);
RayTest ray_test_of(const PointTest& t, const SensorCalibration& cal);

/// Whether the depth point of a pixel (its ray and raw depth) lies inside a box: the labeler's
/// operations in the same order, so the same answer to the bit (the library fuses no multiply-add).
bool holds(const PointTest& t, const Eigen::Vector2f& ray, uint16_t raw);

/// A part of an image: per row, the first and last column it holds (first > last: none of the row).
using RowSpans = std::vector<std::pair<int, int>>;
RowSpans no_pixels(int height);
inline bool empty_span(const std::pair<int, int>& span) { return span.first > span.second; }

Footprint footprint_of(const Box& box, const Pose& T_sensor_world, double near, double far, const DepthView& view);
/// Each box's footprint in a camera at T_world_sensor.
std::vector<Footprint> footprints_of(const std::vector<LabeledBox>& boxes, const SensorCalibration& cal,
                                     const DepthView& view, const Pose& T_world_sensor);

/// The pixels of row v the box can label at most: those of its footprint's rectangle whose ray's x
/// lies within its outline's at the row's heights, widened by a margin far beyond rounding.
std::pair<int, int> candidate_span(const DepthView& view, const Footprint& footprint, int v);

/// The run of row v's pixels whose rays meet the box (first > last: none), searched for only where
/// its footprint's outline can reach.
std::pair<int, int> covered_run(const DepthView& view, const Footprint& footprint, const RayTest& ray_test, int v);

/// What labeling a region counted: its valid, labeled and ambiguous pixels, and per box its pixels
/// there.
struct RegionCounts {
  int valid_pixels = 0, labeled_pixels = 0, ambiguous_pixels = 0;
  std::vector<BoxInFrame> boxes;
};

/// Labels the pixels of `region` afresh (the others are left as they are) with `boxes` in priority
/// order (`footprints`: theirs): each pixel's depth decides whether it can be labeled, then each box
/// labels the depth points inside it that no box before it took. Each box's covered run in a row
/// is found as on the whole image, then cut to the region.
RegionCounts label_region(const cv::Mat& depth, const SensorCalibration& cal, const DepthView& view,
                          const Pose& T_world_sensor, const std::vector<LabeledBox>& boxes,
                          const std::vector<Footprint>& footprints, const RowSpans& region, cv::Mat& class_ids,
                          cv::Mat& instance_ids);

}  // namespace olt::labeling
