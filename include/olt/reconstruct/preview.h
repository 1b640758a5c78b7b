#pragma once
// Pictures of the levelled scene to draw boxes by: two orthographic views of the annotation frame
// side by side, top (x right, y up, looking down) and front (x right, z up, looking along +y), with
// a metric grid labeled in metres, the frame's axes from its origin and a scale bar. Boxes are not in
// the pixels: box_outline() places their 12 edges and names in the same canvas coordinates, for a
// page to draw over the picture (so a picture depends on the scene alone, and moving a box redraws
// no picture it merely shows in). One projection (OrthoView) places the points, the grid, the axes
// and the boxes, so they line up; both views share the scale and the x columns. Nearest point wins;
// pure integer compositing, so the same cloud gives the same bytes.
#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "olt/core/geometry.h"
#include "olt/model/cloud.h"

namespace olt {

/// An axis-aligned region of the annotation frame, metres.
struct Region {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
};

/// The cloud's extent without its stray points: per axis the 0.2% and 99.8% quantiles, widened by
/// `pad_m`; always holds the origin (so the axes are seen).
Region scene_region(const ColoredCloud& cloud, double pad_m);

/// How far the pictures of a whole scene (the reconstruct stage's preview, the report's scene) reach
/// beyond its region each way, metres.
constexpr double kScenePicturePadM = 0.25;

/// One panel: a plane of the annotation frame seen orthographically.
struct OrthoView {
  int axis_v = 1;  ///< 1: top view (x, y), looking down -z; 2: front view (x, z), looking along +y
  cv::Rect panel;  ///< the whole panel in the canvas (title, labels and plot)
  cv::Rect plot;   ///< where the scene is drawn, inside the panel
  double px_per_m = 1;
  Eigen::Vector2d origin_px = Eigen::Vector2d::Zero();  ///< where (0, 0, 0) falls, canvas pixels

  /// Canvas coordinates of a point, sub-pixel: u = origin_u + x s, v = origin_v - (y or z) s.
  Eigen::Vector2d project(const Eigen::Vector3d& p) const;
  /// The canvas pixel holding a point (the floor of project()).
  cv::Point pixel(const Eigen::Vector3d& p) const;
  /// Smaller is nearer the viewer: -z in the top view, y in the front view.
  double depth(const Eigen::Vector3d& p) const { return axis_v == 1 ? -p.z() : p.y(); }
};

struct PreviewLayout {
  cv::Size canvas;
  std::array<OrthoView, 2> views;  ///< top, front
  Region region;                   ///< what is drawn; points outside it are left out
  double grid_step_m = 1;          ///< between grid lines (0.1, 0.2, 0.5, 1, 2, 5 or 10 m)
};

/// Two square panels of `size_px` side by side; one scale fitting `region` in both (x, y) and (x, z);
/// the grid step the smallest whose lines lie `min_grid_px` apart or more.
PreviewLayout preview_layout(const Region& region, int size_px, int min_grid_px = 48);

/// A box to draw: its corners in the annotation frame (box_corners' order), colour, label.
struct PreviewBox {
  std::array<Eigen::Vector3d, 8> corners;
  std::array<uint8_t, 3> rgb{255, 255, 255};
  std::string text;      ///< drawn beside the box, e.g. its id
  int thickness_px = 2;  ///< of its edges
};

/// The 12 edges of a box as pairs of corner indices (corners differing in one sign bit).
constexpr std::array<std::pair<int, int>, 12> kBoxEdges{
    {{0, 1}, {0, 2}, {0, 4}, {1, 3}, {1, 5}, {2, 3}, {2, 6}, {3, 7}, {4, 5}, {4, 6}, {5, 7}, {6, 7}}};

/// A box as one view shows it, in canvas pixels (sub-pixel, unclipped: clip to the view's plot):
/// its corners, and the baseline start of its name (beside its highest corner).
struct BoxOutline {
  std::array<Eigen::Vector2d, 8> corners;
  Eigen::Vector2d text_at = Eigen::Vector2d::Zero();
};
BoxOutline box_outline(const OrthoView& view, const PreviewBox& box);

/// The names' font size for a layout, pixels (as the grid's labels: larger on larger canvases).
double name_font_px(const PreviewLayout& layout);

struct PreviewStyle {
  double point_size_m = 0;  ///< points are squares this wide (at least one pixel): the voxel size
  bool axes = true;         ///< the frame's axes and origin (off where the origin is far away)
  std::string title;        ///< before each panel's "top (x right, y up)"
};

/// Whether the outline of `box` (its edges, `thickness_px` wide, or its name) reaches into either
/// plot: a box that does not may be left out of what is drawn over a picture.
bool box_shows(const PreviewBox& box, const PreviewLayout& layout);

/// A cloud's points ordered by x, for pictures of small regions of a large cloud (a box's, 1.2 M
/// points around it): such a picture looks only at the points whose x is in its region, not at
/// every point. Built once per cloud (a sort); worth it where many pictures are drawn from one cloud
/// (`olt watch` redraws a moved box's picture after each edit).
struct PointsByX {
  size_t cloud_size = 0;       ///< of the cloud it was built from (0: none, or one of over 2^32 points)
  std::vector<uint32_t> by_x;  ///< the points whose x is a number, by x
};
PointsByX points_by_x(const ColoredCloud& cloud);

/// The picture: points (nearest wins; a point with a coordinate that is not a number is not drawn),
/// grid with labels in metres, axes x red, y green, z blue with letters and the origin ringed, a
/// scale bar, panel titles. BGR. With `by_x`, built from this very cloud (the caller's to ensure:
/// only its size is checked), a small region's points are found through it: the same picture.
cv::Mat render_preview(const ColoredCloud& cloud, const PreviewLayout& layout, const PreviewStyle& style,
                       const PointsByX* by_x = nullptr);

}  // namespace olt
