// Relabeling after an edit (relabel_depth_image) against labeling afresh (label_depth_image): the
// same images and counts, bit for bit, on random scenes and every kind of edit.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>

#include "olt/core/image_strips.h"
#include "olt/propagate/propagate.h"
#include "olt/propagate/visibility.h"

using namespace olt;

namespace {

// A 160x120 camera with f = 150 px and a little barrel distortion.
SensorCalibration camera() {
  SensorCalibration cal;
  cal.depth = {160, 120, 150, 150, 79.5, 59.5, {-0.05, 0.01, 0, 0, 0}};
  cal.color = cal.depth;
  cal.depth_scale = 1000;
  cal.min_depth_m = 0.3;
  cal.max_depth_m = 4;
  return cal;
}

// A slanted floor-like surface 1-3.5 m away, with holes (no reading) and a near step.
cv::Mat scene_depth(std::mt19937& random) {
  cv::Mat depth(120, 160, CV_16UC1);
  std::uniform_int_distribution<int> noise(-15, 15), hole(0, 40);
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      int mm = 1000 + 20 * v + 3 * u + noise(random);
      if (u > 100 && v > 60) mm -= 600;  // a step towards the camera
      depth.at<uint16_t>(v, u) = hole(random) == 0 ? 0 : static_cast<uint16_t>(mm);
    }
  return depth;
}

Box random_box(const std::string& id, std::mt19937& random) {
  std::uniform_real_distribution<double> x(-0.8, 0.8), z(1.0, 3.2), angle(-40, 40), side(0.1, 0.9);
  std::uniform_int_distribution<int> priority(0, 2);
  Box b;
  b.id = id;
  b.label = "thing" + std::to_string(priority(random));
  b.instance = id;
  b.T_world_box = pose_from_xyz_ypr_deg({x(random), 0.6 * x(random), z(random), angle(random), angle(random), 0});
  b.size = {side(random), side(random), side(random)};
  b.priority = priority(random) == 0 ? 1 : 0;
  return b;
}

// The rectangle of the pixels of `ids` equal to `id`.
cv::Rect rect_of(const cv::Mat& ids, uint16_t id) {
  std::vector<cv::Point> points;
  cv::findNonZero(ids == id, points);
  return cv::boundingRect(points);
}

void check_same(const FrameLabels& got, const FrameLabels& expected) {
  CHECK(cv::countNonZero(got.class_ids != expected.class_ids) == 0);
  CHECK(cv::countNonZero(got.instance_ids != expected.instance_ids) == 0);
  CHECK(got.valid_pixels == expected.valid_pixels);
  CHECK(got.labeled_pixels == expected.labeled_pixels);
  CHECK(got.ambiguous_pixels == expected.ambiguous_pixels);
  REQUIRE(got.boxes.size() == expected.boxes.size());
  for (size_t k = 0; k < got.boxes.size(); ++k) {
    INFO("box " << k);
    CHECK(got.boxes[k].labeled_pixels == expected.boxes[k].labeled_pixels);
    CHECK(got.boxes[k].covered_pixels == expected.boxes[k].covered_pixels);
    CHECK(got.boxes[k].bottom_pixels == expected.boxes[k].bottom_pixels);
    CHECK(got.boxes[k].bbox == expected.boxes[k].bbox);
  }
}

}  // namespace

TEST_CASE("relabeling after an edit gives the labels and counts of labeling afresh, on random scenes") {
  // Half the scenes through a strongly distorted lens, whose rows' rays fold back at the corners
  // (where the labeler searches a box's whole rectangle rather than its outline).
  SensorCalibration folding = camera();
  folding.depth.distortion = {-0.4, 0, 0, 0, 0};  // 26 of its 120 rows fold
  folding.color = folding.depth;
  const DepthView plain_view = make_depth_view(camera().depth), folding_view = make_depth_view(folding.depth);
  REQUIRE(std::count(folding_view.row_x_ascending.begin(), folding_view.row_x_ascending.end(), false) > 0);
  std::mt19937 random(20261126);
  const std::vector<std::string> edits = {"move one",         "move all",          "remove one",       "add one",
                                          "raise a priority", "share an instance", "move out of view", "nothing"};
  int pixels_changed = 0, in_place = 0, afresh = 0, second_in_place = 0;
  for (int scene = 0; scene < 12; ++scene) {
    const SensorCalibration cal = scene % 2 == 0 ? camera() : folding;
    const DepthView& view = scene % 2 == 0 ? plain_view : folding_view;
    const cv::Mat depth = scene_depth(random);
    std::vector<Box> before;
    for (int i = 0; i < 7; ++i) before.push_back(random_box("b" + std::to_string(i), random));
    before[6].instance = before[5].instance;  // one object of two boxes, as a desk with its return
    before[6].label = before[5].label;
    const Pose T_world_sensor = pose_from_xyz_ypr_deg({0, 0, 0, 0, 0, scene % 3 == 0 ? 5.0 : 0.0});
    for (const auto& edit : edits) {
      INFO("scene " << scene << ", edit: " << edit);
      std::vector<Box> after = before;
      std::uniform_int_distribution<size_t> pick(0, after.size() - 1);
      const size_t k = pick(random);
      if (edit == "move one") after[k].T_world_box.translation() += Eigen::Vector3d(0.05, -0.02, 0.03);
      if (edit == "move all")
        for (auto& b : after) b.T_world_box.translation().z() += 0.04;
      if (edit == "remove one") after.erase(after.begin() + static_cast<long>(k));
      if (edit == "add one") after.push_back(random_box("new", random));
      if (edit == "raise a priority") after[k].priority = 5;
      if (edit == "move out of view") after[k].T_world_box.translation().x() += 20;
      if (edit == "share an instance") {  // two boxes of one object: one instance, one class
        after[k].instance = after[(k + 1) % after.size()].instance;
        after[k].label = after[(k + 1) % after.size()].label;
      }
      // One map for both sides, as when an edit leaves the label map as it was.
      std::vector<Box> all = before;
      all.insert(all.end(), after.begin(), after.end());
      const LabelMap map = make_label_map(all, {});
      const auto old_boxes = prioritized_boxes(before, map), new_boxes = prioritized_boxes(after, map);
      const FrameLabels previous = label_depth_image(depth, cal, view, T_world_sensor, old_boxes);
      const FrameLabels expected = label_depth_image(depth, cal, view, T_world_sensor, new_boxes);
      const auto relabeled = relabel_depth_image(depth, cal, view, T_world_sensor, new_boxes, old_boxes, previous);
      // The same, labeled over the previous labels' own images (as the labeling stage labels a frame
      // nothing else holds): they are asked for once, with the rows labeled again, and labeled in.
      FrameLabels own = previous;
      own.class_ids = previous.class_ids.clone(), own.instance_ids = previous.instance_ids.clone();
      const uchar* own_pixels = own.class_ids.data;
      std::vector<std::vector<bool>> asked;
      const auto over = relabel_depth_image(depth, cal, view, T_world_sensor, new_boxes, old_boxes, own,
                                            [&](const std::vector<bool>& rows) {
                                              asked.push_back(rows);
                                              return std::pair{own.class_ids, own.instance_ids};
                                            });
      if (!relabeled) {  // more than half the image to label again: labeled afresh instead
        CHECK(!over);
        CHECK(asked.empty());  // nor were the images asked for
        ++afresh;
        continue;
      }
      ++in_place;
      check_same(*relabeled, expected);
      REQUIRE(over);
      check_same(*over, expected);
      REQUIRE(asked.size() == 1);
      CHECK(asked[0] == over->rows_relabeled);
      CHECK(over->class_ids.data == own_pixels);
      // What the labeling stage takes from it: the rows that can differ (the others are the previous
      // bytes), and the boxes' footprints, as labeling afresh finds them.
      CHECK(differing_rows(relabeled->class_ids, previous.class_ids, relabeled->rows_relabeled) ==
            differing_rows(relabeled->class_ids, previous.class_ids));
      CHECK(differing_rows(relabeled->instance_ids, previous.instance_ids, relabeled->rows_relabeled) ==
            differing_rows(relabeled->instance_ids, previous.instance_ids));
      REQUIRE(relabeled->footprints.size() == expected.footprints.size());
      for (size_t b = 0; b < expected.footprints.size(); ++b) {
        CHECK(relabeled->footprints[b].rect == expected.footprints[b].rect);
        CHECK(relabeled->footprints[b].outline == expected.footprints[b].outline);
      }
      FrameLabels bare = previous;  // labels without the boxes' footprints: each found again
      bare.footprints.clear();
      const auto from_bare = relabel_depth_image(depth, cal, view, T_world_sensor, new_boxes, old_boxes, bare);
      REQUIRE(from_bare);
      check_same(*from_bare, expected);
      pixels_changed += cv::countNonZero(previous.instance_ids != expected.instance_ids);
      // A second edit, from the labels the first left: one box moved back a little.
      std::vector<Box> again = after;
      if (!again.empty()) again[0].T_world_box.translation() += Eigen::Vector3d(-0.03, 0.01, 0);
      const auto again_boxes = prioritized_boxes(again, map);
      const auto second = relabel_depth_image(depth, cal, view, T_world_sensor, again_boxes, new_boxes, *relabeled);
      if (second) {
        ++second_in_place;
        check_same(*second, label_depth_image(depth, cal, view, T_world_sensor, again_boxes));
      }
    }
  }
  CHECK(pixels_changed > 1000);  // the edits did change labels: the comparison is not of unchanged images
  CHECK(in_place > 50);          // most edits are relabeled in place (of 96)
  CHECK(afresh > 0);             // moving every box reaches most of the image
  CHECK(second_in_place > 40);   // and most second edits, from labels a relabel left
}

TEST_CASE("relabeling keeps the previous labels outside the footprints of the boxes that changed") {
  const SensorCalibration cal = camera();
  const DepthView view = make_depth_view(cal.depth);
  const cv::Mat depth(120, 160, CV_16UC1, cv::Scalar(2000));  // a wall 2 m away
  Box left, right;
  left.id = "left", left.label = "a", left.instance = "left";
  left.T_world_box = pose_from_xyz_ypr_deg({-0.8, 0, 2, 0, 0, 0});
  left.size = {0.4, 0.4, 0.4};
  right = left;
  right.id = "right", right.instance = "right";
  right.T_world_box = pose_from_xyz_ypr_deg({0.8, 0, 2, 0, 0, 0});
  const LabelMap map = make_label_map({left, right}, {});
  const auto old_boxes = prioritized_boxes({left, right}, map);
  FrameLabels previous = label_depth_image(depth, cal, view, Pose::Identity(), old_boxes);
  // The left box's pixels (u < 60) marked in the previous labels: a relabel that labeled them again
  // would undo the mark, one that reuses them keeps it.
  REQUIRE(previous.instance_ids.at<uint16_t>(60, 30) == map.instance_id("left"));
  previous.instance_ids.at<uint16_t>(60, 30) = 77;
  right.T_world_box.translation().y() += 0.1;  // the right box moved: the left box's pixels stay
  const auto new_boxes = prioritized_boxes({left, right}, map);
  const auto in_place = relabel_depth_image(depth, cal, view, Pose::Identity(), new_boxes, old_boxes, previous);
  REQUIRE(in_place);
  const FrameLabels& relabeled = *in_place;
  CHECK(relabeled.instance_ids.at<uint16_t>(60, 30) == 77);
  const FrameLabels fresh = label_depth_image(depth, cal, view, Pose::Identity(), new_boxes);
  cv::Mat right_half = relabeled.instance_ids.colRange(80, 160) != fresh.instance_ids.colRange(80, 160);
  CHECK(cv::countNonZero(right_half) == 0);  // the moved box's side is labeled afresh
  CHECK(cv::countNonZero(previous.instance_ids != fresh.instance_ids) > 100);
}

TEST_CASE("relabeling finds the rectangle a box grows to in the region, away from the pixels it kept") {
  // A wall 2 m away; box B spans it from x = -0.8 to 0.6 m; C (priority 1) takes x = -0.4..0.05 from
  // it and A (priority 2) x = 0..0.6. Removing A gives B the right part back: its rectangle grows
  // there, away from the pixels it labeled before (C's stay between).
  const SensorCalibration cal = camera();
  const DepthView view = make_depth_view(cal.depth);
  const cv::Mat depth(120, 160, CV_16UC1, cv::Scalar(2000));
  const auto slab = [](const std::string& id, double x0, double x1, int priority) {
    Box b;
    b.id = id, b.label = id, b.instance = id, b.priority = priority;
    b.T_world_box = pose_from_xyz_ypr_deg({(x0 + x1) / 2, 0, 2, 0, 0, 0});
    b.size = {x1 - x0, 0.5, 0.4};
    return b;
  };
  const Box a = slab("a", 0, 0.6, 2), b = slab("b", -0.8, 0.6, 0), c = slab("c", -0.4, 0.05, 1);
  const LabelMap map = make_label_map({a, b, c}, {});
  const auto old_boxes = prioritized_boxes({a, b, c}, map), new_boxes = prioritized_boxes({b, c}, map);
  const FrameLabels previous = label_depth_image(depth, cal, view, Pose::Identity(), old_boxes);
  const FrameLabels expected = label_depth_image(depth, cal, view, Pose::Identity(), new_boxes);
  const auto relabeled = relabel_depth_image(depth, cal, view, Pose::Identity(), new_boxes, old_boxes, previous);
  REQUIRE(relabeled);
  check_same(*relabeled, expected);
  const cv::Rect before = previous.boxes[2].bbox, after = expected.boxes[1].bbox;  // B: last, then after C
  REQUIRE(old_boxes[2].box.id == "b");
  REQUIRE(new_boxes[1].box.id == "b");
  CHECK(before.br().x + 20 < after.br().x);  // grew to the right, far from where it was
}

namespace {

// A wall 2 m away; a desk of two boxes (one instance): its top (x = -0.6..0.2 m, smaller: first) and
// its return (x = -0.1..0.9 m), overlapping at x = -0.1..0.2, which the top labels; a mug (priority 1,
// `mug_height` m tall) in front of the return at x = 0.3..0.4 m moves `mug_moves_m` along x. The
// labels before and after the move, and the relabel.
struct DeskEdit {
  LabelMap map;
  std::vector<LabeledBox> new_boxes;
  FrameLabels previous, expected;
  std::optional<FrameLabels> relabeled;
};

DeskEdit desk_edit(double mug_height, double mug_moves_m) {
  const SensorCalibration cal = camera();
  const DepthView view = make_depth_view(cal.depth);
  const cv::Mat depth(120, 160, CV_16UC1, cv::Scalar(2000));
  const auto slab = [](const std::string& id, const std::string& instance, double x0, double x1, double height,
                       int priority) {
    Box b;
    b.id = id, b.label = instance, b.instance = instance, b.priority = priority;
    b.T_world_box = pose_from_xyz_ypr_deg({(x0 + x1) / 2, 0, 2, 0, 0, 0});
    b.size = {x1 - x0, height, 0.4};
    return b;
  };
  const Box top = slab("top", "desk", -0.6, 0.2, 0.3, 0), side = slab("return", "desk", -0.1, 0.9, 0.3, 0);
  Box mug = slab("mug", "mug", 0.3, 0.4, mug_height, 1);
  DeskEdit edit;
  edit.map = make_label_map({top, side, mug}, {});
  const auto old_boxes = prioritized_boxes({top, side, mug}, edit.map);
  mug.T_world_box.translation().x() += mug_moves_m;
  edit.new_boxes = prioritized_boxes({top, side, mug}, edit.map);
  edit.previous = label_depth_image(depth, cal, view, Pose::Identity(), old_boxes);
  edit.expected = label_depth_image(depth, cal, view, Pose::Identity(), edit.new_boxes);
  edit.relabeled = relabel_depth_image(depth, cal, view, Pose::Identity(), edit.new_boxes, old_boxes, edit.previous);
  return edit;
}

}  // namespace

TEST_CASE("relabeling finds the rectangle of a box that shares its instance, apart from the other box's pixels") {
  // The mug moves 0.1 m along the return. The return's rectangle must leave out the overlap, although
  // its instance holds it there.
  const DeskEdit edit = desk_edit(0.1, 0.1);
  REQUIRE(edit.new_boxes[1].box.id == "top");  // the mug first (priority), then the smaller desk box
  REQUIRE(edit.new_boxes[2].box.id == "return");
  REQUIRE(edit.relabeled);
  check_same(*edit.relabeled, edit.expected);
  // The return's rectangle starts right of the overlap (x = 0.2 m: u = 79.5 + 0.1 * 150 = 94.5),
  // where the instance image has the desk from x = -0.6 m (u = 34.5).
  CHECK(edit.expected.boxes[2].bbox.x > 90);
  CHECK(rect_of(edit.expected.instance_ids, edit.map.instance_id("desk")).x < 40);
}

TEST_CASE(
    "relabeling finds the rectangle a box that shares its instance shrinks to, where a box in front took its edge") {
  // A mug taller than the desk (it takes whole columns) moves from the middle of the return to its
  // right end (x = 0.8..0.9 m), taking the pixels the return's rectangle ended at: the rectangle's right
  // side was held only by pixels in the region labeled again.
  const DeskEdit edit = desk_edit(0.4, 0.5);
  REQUIRE(edit.new_boxes[2].box.id == "return");
  REQUIRE(edit.relabeled);
  check_same(*edit.relabeled, edit.expected);
  // The return ended at x = 0.9 m (u = 79.5 + 0.45 * 150 = 147); now the mug's 0.8 m (u = 139.5) ends it.
  CHECK(edit.previous.boxes[2].bbox.br().x > 144);
  CHECK(edit.expected.boxes[2].bbox.br().x < 142);
}
