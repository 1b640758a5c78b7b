#pragma once
// Label propagation (paper Sec. III-E): every valid depth pixel is back-projected with the depth
// intrinsics (undistorted) and the observation's pose; a point inside a box takes that box's class
// and instance. Overlaps: an explicit per-box priority wins, then the box of smallest volume (ties:
// the smaller box id), so an object resting on or inside a larger one keeps its own label. Testing depth points, not
// projected box shapes, makes the result occlusion-correct by construction.
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "olt/core/box.h"
#include "olt/model/cloud.h"
#include "olt/model/recording.h"
#include "olt/propagate/label_map.h"
#include "olt/propagate/visibility.h"

namespace olt {

struct LabeledBox {
  Box box;
  uint16_t class_id = 0;
  uint16_t instance_id = 0;
};

/// Boxes with their ids, in the order the overlap rule tries them: higher `priority` first, then
/// smaller volume, then id. Each is its labeling part (bottom raised by its margin).
std::vector<LabeledBox> prioritized_boxes(const std::vector<Box>& boxes, const LabelMap& map);

/// What one box did in one frame.
/// The band above a box's bottom face where the surface it stands on would lie, metres.
inline constexpr float kBottomBand = 0.02f;

/// Where a box can label in a camera: its footprint's rectangle and outline.
struct Footprint {
  cv::Rect rect;
  std::vector<cv::Point2f> outline;
};

struct BoxInFrame {
  int labeled_pixels = 0;  ///< pixels it labeled (after the overlap rule)
  int covered_pixels = 0;  ///< pixels whose ray passes through the box within the depth range
  int bottom_pixels = 0;   ///< of the labeled, those within kBottomBand of its bottom face
  cv::Rect bbox;           ///< of the pixels it labeled; empty when none
};

struct FrameLabels {
  cv::Mat class_ids;              ///< CV_16UC1 at depth resolution; kUnlabeled, class id, or kNoDepth
  cv::Mat instance_ids;           ///< CV_16UC1 at depth resolution; kUnlabeled, instance id, or kNoDepth
  int valid_pixels = 0;           ///< pixels with depth inside the sensor's range
  int labeled_pixels = 0;         ///< pixels inside at least one box
  int ambiguous_pixels = 0;       ///< pixels inside more than one box (resolved by the overlap rule)
  std::vector<BoxInFrame> boxes;  ///< per prioritized box
  /// Per prioritized box, where it can label: relabeling in place takes an unchanged box's from here.
  std::vector<Footprint> footprints;
  /// The rows relabel_depth_image labeled again (the others hold the previous labels, byte for byte);
  /// empty where the frame was labeled afresh.
  std::vector<bool> rows_relabeled;
};

/// Labels one depth image. Depth outside [min_depth_m, max_depth_m] counts as no depth. Only
/// boxes in view are tested, and each only on the pixels of its footprint.
FrameLabels label_depth_image(const cv::Mat& depth, const SensorCalibration& calibration, const DepthView& view,
                              const Pose& T_world_sensor, const std::vector<LabeledBox>& boxes);

/// The labels of a frame after an edit, from its labels before it: `previous` is what
/// label_depth_image made of the same depth with `previous_boxes` (in priority order). Only the pixels
/// a changed box can reach (before or after the edit) are labeled again; the rest, and the counts of
/// the other boxes (corrected by what changed in those pixels), are the previous ones. The result is
/// label_depth_image's with `boxes`, bit for bit. None where the pixels to label again are more than
/// half the image: they are labeled twice (as before the edit, and now), so labeling afresh is less.
std::optional<FrameLabels> relabel_depth_image(const cv::Mat& depth, const SensorCalibration& calibration,
                                               const DepthView& view, const Pose& T_world_sensor,
                                               const std::vector<LabeledBox>& boxes,
                                               const std::vector<LabeledBox>& previous_boxes,
                                               const FrameLabels& previous);

/// The class and instance images relabel_depth_image labels in, holding `previous`'s labels, asked
/// for once the rows it labels again are known (a flag per row) and before it labels any: copies of
/// them (as the call above makes), or, where nobody reads them after, `previous`'s own images once
/// the caller kept what it needs of them. Asked for at most once, and then the labels are returned
/// (never none) and `previous`'s images are not read again: the caller may give those very images.
using ImagesToRelabel = std::function<std::pair<cv::Mat, cv::Mat>(const std::vector<bool>& rows)>;
std::optional<FrameLabels> relabel_depth_image(const cv::Mat& depth, const SensorCalibration& calibration,
                                               const DepthView& view, const Pose& T_world_sensor,
                                               const std::vector<LabeledBox>& boxes,
                                               const std::vector<LabeledBox>& previous_boxes,
                                               const FrameLabels& previous, const ImagesToRelabel& images);

/// Labels at colour resolution (CV_16UC1, the colour camera's size).
struct ColorLabels {
  cv::Mat class_ids;
  cv::Mat instance_ids;
};

/// The depth labels carried to the colour camera: every valid depth point moved by T_color_depth
/// and projected with the colour intrinsics (distortion included); where several reach one colour
/// pixel, the nearest wins (z-buffer), so colour pixels take the label of what is in front.
/// Colour pixels no point reaches are kNoDepth, or, with fill_px > 0, take the label of the
/// nearest reached pixel within fill_px whose depth is within fill_tolerance_m of the nearest
/// depth in that window (the front surface, so an edge does not bleed the background into it).
/// When the colour camera is the depth camera (registered depth), the labels are the same.
/// True when the colour images are taken by the depth camera itself (registered depth): same
/// intrinsics and size, identity transform. Colour labels are then the depth labels.
bool color_is_depth_camera(const SensorCalibration& calibration);

ColorLabels label_color_image(const FrameLabels& labels, const cv::Mat& depth, const SensorCalibration& calibration,
                              const DepthView& view, int fill_px, double fill_tolerance_m);

/// Every valid depth point in the sensor frame with its class and instance, coloured from the colour
/// image where it projects into it (black where it does not, or without a colour image).
LabeledCloud labeled_cloud(const FrameLabels& labels, const cv::Mat& depth, const cv::Mat& color_bgr,
                           const SensorCalibration& calibration, const DepthView& view);

/// Whether `box` can label pixels of a camera that sees the world as `T_sensor_world` maps it (the
/// inverse of its pose).
bool box_in_view(const LabeledBox& box, const SensorCalibration& calibration, const DepthView& view,
                 const Pose& T_sensor_world);

/// Indices (into `boxes`) of the boxes that can label pixels of a camera at `T_world_sensor`.
std::vector<size_t> boxes_in_view(const std::vector<LabeledBox>& boxes, const SensorCalibration& calibration,
                                  const DepthView& view, const Pose& T_world_sensor);

/// For people: the colour (or depth) image with class colours blended in and box outlines drawn.
/// With `rows` (a flag per row), only the rows flagged are drawn, whole; the others are undefined (for
/// a picture encoded again only in those rows).
cv::Mat render_overlay(const cv::Mat& color_bgr, const cv::Mat& depth, const FrameLabels& labels, const LabelMap& map,
                       const std::vector<LabeledBox>& boxes, const SensorCalibration& calibration,
                       const Pose& T_world_sensor, const std::vector<bool>& rows = {});

/// The rows of render_overlay's picture that can differ between a frame labeled with `previous_boxes`
/// and labeled with `boxes` (the same images, calibration and pose): those where the class ids differ
/// (`classes_differ`, a flag per row: differing_rows of the two class images), and those the outline
/// of a box runs through (before or now) where the boxes differ at its place in the order.
std::vector<bool> overlay_rows_changed(std::vector<bool> classes_differ, const std::vector<LabeledBox>& boxes,
                                       const std::vector<LabeledBox>& previous_boxes, const SensorCalibration& cal,
                                       const Pose& T_world_sensor);

}  // namespace olt
