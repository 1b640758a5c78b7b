// Relabeling in place (relabel_depth_image): only the pixels the changed boxes reach.
#include <algorithm>
#include <optional>

#include "labeler.h"
#include "olt/propagate/propagate.h"

namespace olt {
using namespace labeling;
namespace {

// Widens `region`'s rows to hold the pixels a box can label (each row's candidates).
void add_footprint(const DepthView& view, const Footprint& f, RowSpans& region) {
  for (int v = f.rect.y; v < f.rect.y + f.rect.height; ++v) {
    const std::pair<int, int> span = candidate_span(view, f, v);
    if (empty_span(span)) continue;
    auto& row = region[static_cast<size_t>(v)];
    row = empty_span(row) ? span
                          : std::pair<int, int>{std::min(row.first, span.first), std::max(row.second, span.second)};
  }
}

// True when a pixel of `rect` is in `region`.
bool rect_meets(const cv::Rect& rect, const RowSpans& region) {
  for (int v = rect.y; v < rect.y + rect.height; ++v) {
    const auto& row = region[static_cast<size_t>(v)];
    if (!empty_span(row) && row.first <= rect.x + rect.width - 1 && rect.x <= row.second) return true;
  }
  return false;
}

// The rectangle of the pixels of `ids` that are `id` in `within`, each row searched from both ends.
cv::Rect rect_of(const cv::Mat& ids, uint16_t id, cv::Rect within) {
  within &= cv::Rect(0, 0, ids.cols, ids.rows);
  int u_min = INT32_MAX, v_min = INT32_MAX, u_max = -1, v_max = -1;
  for (int v = within.y; v < within.y + within.height; ++v) {
    const uint16_t* row = ids.ptr<uint16_t>(v);
    int first = within.x, last = within.x + within.width - 1;
    while (first <= last && row[first] != id) ++first;
    if (first > last) continue;
    while (row[last] != id) --last;
    u_min = std::min(u_min, first), u_max = std::max(u_max, last);
    v_min = std::min(v_min, v), v_max = v;
  }
  return u_max < 0 ? cv::Rect() : cv::Rect(u_min, v_min, u_max - u_min + 1, v_max - v_min + 1);
}

// Which pixels box k labels, as the labeler decides: in its covered run (the pixels of a row whose rays
// meet it, found as the labeler finds them), its instance there, its point held, and no box of the
// same instance before it holding it (another box of the instance may have labeled it). Where no other
// box has its instance, every pixel of the instance is its own.
struct BoxPixels {
  BoxPixels(const cv::Mat& ids, const cv::Mat& depth, const DepthView& view, const SensorCalibration& cal,
            const Pose& T_world_sensor, const std::vector<LabeledBox>& boxes, size_t k, const Footprint& footprint)
      : ids(ids),
        depth(depth),
        view(view),
        footprint(footprint),
        id(boxes[k].instance_id),
        own(point_test_of(boxes[k].box, T_world_sensor, cal)),
        ray(ray_test_of(own, cal)),
        runs(static_cast<size_t>(std::max(0, footprint.rect.height))) {
    for (size_t j = 0; j < k; ++j)
      if (boxes[j].instance_id == id) before.push_back(point_test_of(boxes[j].box, T_world_sensor, cal));
    alone = before.empty() && std::none_of(boxes.begin() + static_cast<long>(k) + 1, boxes.end(),
                                           [&](const LabeledBox& b) { return b.instance_id == id; });
  }

  // Row v's covered run (first > last: none), found once.
  std::pair<int, int> covered(int v) {
    if (v < footprint.rect.y || v >= footprint.rect.y + footprint.rect.height) return {0, -1};
    auto& run = runs[static_cast<size_t>(v - footprint.rect.y)];
    if (!run) run = covered_run(view, footprint, ray, v);
    return *run;
  }

  bool labels(int u, int v) {
    if (ids.at<uint16_t>(v, u) != id) return false;
    if (alone) return true;
    const auto [first, last] = covered(v);
    if (u < first || u > last) return false;
    const Eigen::Vector2f& r = view.rays[static_cast<size_t>(v) * view.width + u];
    const uint16_t raw = depth.at<uint16_t>(v, u);
    return holds(own, r, raw) &&
           std::none_of(before.begin(), before.end(), [&](const PointTest& t) { return holds(t, r, raw); });
  }

  const cv::Mat& ids;
  const cv::Mat& depth;
  const DepthView& view;
  const Footprint& footprint;
  uint16_t id;
  PointTest own;
  RayTest ray;
  std::vector<PointTest> before;  // the boxes of its instance that come first
  bool alone = false;
  std::vector<std::optional<std::pair<int, int>>> runs;  // per row of the footprint's rectangle
};

// The rectangle of the pixels a box labels: each row's covered run searched from both ends only;
// where no other box has its instance, the instance's pixels in its footprint's rectangle.
cv::Rect labeled_rect(BoxPixels& box) {
  if (box.alone) return rect_of(box.ids, box.id, box.footprint.rect);
  const cv::Rect& rect = box.footprint.rect;
  int u_min = INT32_MAX, v_min = INT32_MAX, u_max = -1, v_max = -1;
  for (int v = rect.y; v < rect.y + rect.height; ++v) {
    const auto [covered_from, covered_to] = box.covered(v);
    int first = covered_from;
    while (first <= covered_to && !box.labels(first, v)) ++first;
    if (first > covered_to) continue;
    int last = covered_to;
    while (last > first && !box.labels(last, v)) --last;
    u_min = std::min(u_min, first), u_max = std::max(u_max, last);
    v_min = std::min(v_min, v), v_max = v;
  }
  return u_max < 0 ? cv::Rect() : cv::Rect(u_min, v_min, u_max - u_min + 1, v_max - v_min + 1);
}

// Whether each of the four sides of `rect` (the pixels a box labeled before the edit) holds a pixel
// the box still labels outside `region`: the labels there did not change, so the box's rectangle still
// reaches every side, and only what it labels in the region can widen it. Scans the sides only: a
// desk whose mug moved is not searched again over its whole footprint.
bool sides_kept_outside(const cv::Rect& rect, const RowSpans& region, BoxPixels& box) {
  const auto kept = [&](int u, int v) {
    const auto& row = region[static_cast<size_t>(v)];
    return (empty_span(row) || u < row.first || u > row.second) && box.labels(u, v);
  };
  const auto row_kept = [&](int v) {
    for (int u = rect.x; u < rect.x + rect.width; ++u)
      if (kept(u, v)) return true;
    return false;
  };
  const auto column_kept = [&](int u) {
    for (int v = rect.y; v < rect.y + rect.height; ++v)
      if (kept(u, v)) return true;
    return false;
  };
  return row_kept(rect.y) && row_kept(rect.y + rect.height - 1) && column_kept(rect.x) &&
         column_kept(rect.x + rect.width - 1);
}

// The same box, labeling the same pixels: its id, ids, priority and labeling part's geometry.
bool same_labeling(const LabeledBox& a, const LabeledBox& b) {
  return a.box.id == b.box.id && a.class_id == b.class_id && a.instance_id == b.instance_id &&
         a.box.priority == b.box.priority && a.box.size == b.box.size &&
         a.box.T_world_box.matrix() == b.box.T_world_box.matrix();
}

// Per box of `boxes`, the position of the same box in `others`, or none.
std::vector<std::optional<size_t>> twins(const std::vector<LabeledBox>& boxes, const std::vector<LabeledBox>& others) {
  std::vector<std::optional<size_t>> out(boxes.size());
  for (size_t k = 0; k < boxes.size(); ++k)
    for (size_t j = 0; j < others.size() && !out[k]; ++j)
      if (same_labeling(boxes[k], others[j])) out[k] = j;
  return out;
}

}  // namespace

std::optional<FrameLabels> relabel_depth_image(const cv::Mat& depth, const SensorCalibration& cal,
                                               const DepthView& view, const Pose& T_world_sensor,
                                               const std::vector<LabeledBox>& boxes,
                                               const std::vector<LabeledBox>& previous_boxes,
                                               const FrameLabels& previous) {
  return relabel_depth_image(depth, cal, view, T_world_sensor, boxes, previous_boxes, previous,
                             [&](const std::vector<bool>&) {
                               return std::pair{previous.class_ids.clone(), previous.instance_ids.clone()};
                             });
}

std::optional<FrameLabels> relabel_depth_image(const cv::Mat& depth, const SensorCalibration& cal,
                                               const DepthView& view, const Pose& T_world_sensor,
                                               const std::vector<LabeledBox>& boxes,
                                               const std::vector<LabeledBox>& previous_boxes,
                                               const FrameLabels& previous, const ImagesToRelabel& images) {
  const Pose T_sensor_world = T_world_sensor.inverse();
  const auto now_twins = twins(boxes, previous_boxes), before_twins = twins(previous_boxes, boxes);
  // The boxes' footprints: a box that did not change has the one it had (the frame's pose and camera
  // are the same), found again only where the previous labels do not hold them.
  const bool footprints_kept = previous.footprints.size() == previous_boxes.size();
  const auto footprint = [&](const Box& box) {
    return footprint_of(box, T_sensor_world, near_limit(cal), cal.max_depth_m, view);
  };
  std::vector<Footprint> footprints, footprints_before;
  for (size_t k = 0; k < boxes.size(); ++k)
    footprints.push_back(now_twins[k] && footprints_kept ? previous.footprints[*now_twins[k]]
                                                         : footprint(boxes[k].box));
  for (size_t j = 0; j < previous_boxes.size(); ++j)
    footprints_before.push_back(footprints_kept   ? previous.footprints[j]
                                : before_twins[j] ? footprints[*before_twins[j]]
                                                  : footprint(previous_boxes[j].box));
  // Labeled again: the pixels a changed box can reach, before or after (each one's whole footprint).
  // The region is labeled twice (as before the edit, and now): beyond half the image, labeling the
  // whole image once is less work, and the search stops there.
  RowSpans region = no_pixels(depth.rows);
  const auto beyond_half = [&] {
    int64_t area = 0;
    for (const auto& row : region) area += empty_span(row) ? 0 : row.second - row.first + 1;
    return 2 * area > static_cast<int64_t>(depth.rows) * depth.cols;
  };
  for (size_t k = 0; k < boxes.size(); ++k)
    if (!now_twins[k]) {
      add_footprint(view, footprints[k], region);
      if (beyond_half()) return std::nullopt;
    }
  for (size_t j = 0; j < previous_boxes.size(); ++j)
    if (!before_twins[j]) {
      add_footprint(view, footprints_before[j], region);
      if (beyond_half()) return std::nullopt;
    }
  std::vector<bool> rows;
  for (const auto& row : region) rows.push_back(!empty_span(row));
  auto [class_ids, instance_ids] = images(rows);  // from here on, labeled: previous's images may be these
  CV_Assert(class_ids.size() == depth.size() && class_ids.type() == CV_16UC1 && instance_ids.size() == depth.size() &&
            instance_ids.type() == CV_16UC1);
  FrameLabels out{std::move(class_ids), std::move(instance_ids), previous.valid_pixels, 0, 0, {}, {}, std::move(rows)};
  // The region's counts as the previous boxes left them, then as the boxes leave them now.
  const RegionCounts before = label_region(depth, cal, view, T_world_sensor, previous_boxes, footprints_before, region,
                                           out.class_ids, out.instance_ids);
  const RegionCounts now =
      label_region(depth, cal, view, T_world_sensor, boxes, footprints, region, out.class_ids, out.instance_ids);
  out.labeled_pixels = previous.labeled_pixels - before.labeled_pixels + now.labeled_pixels;
  out.ambiguous_pixels = previous.ambiguous_pixels - before.ambiguous_pixels + now.ambiguous_pixels;
  for (size_t k = 0; k < boxes.size(); ++k) {
    if (!now_twins[k]) {  // a changed box: every pixel it covers was labeled again
      out.boxes.push_back(now.boxes[k]);
      continue;
    }
    // A box that did not change covers what it covered; what it labels changed only in the region.
    const size_t j = *now_twins[k];
    BoxInFrame seen = previous.boxes[j];
    seen.labeled_pixels += now.boxes[k].labeled_pixels - before.boxes[j].labeled_pixels;
    seen.bottom_pixels += now.boxes[k].bottom_pixels - before.boxes[j].bottom_pixels;
    // Its rectangle: where the pixels it labeled before still reach every side of the previous one
    // (all of them outside the region, or one on each side), that one joined with what it labels in
    // the region; else found in the new labels.
    const cv::Rect& inside = now.boxes[k].bbox;
    const cv::Rect joined = seen.bbox.empty() ? inside : inside.empty() ? seen.bbox : (seen.bbox | inside);
    if (rect_meets(seen.bbox, region)) {
      BoxPixels box(out.instance_ids, depth, view, cal, T_world_sensor, boxes, k, footprints[k]);
      seen.bbox = sides_kept_outside(seen.bbox, region, box) ? joined : labeled_rect(box);
    } else {
      seen.bbox = joined;
    }
    out.boxes.push_back(seen);
  }
  out.footprints = std::move(footprints);
  return out;
}

}  // namespace olt
