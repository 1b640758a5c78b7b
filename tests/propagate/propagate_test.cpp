#include "olt/propagate/propagate.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"

using namespace olt;

namespace {

// A 101x101 camera with f = 100 px looking at a wall 2 m away: pixel u sees x = (u - 50) / 50 m.
SensorCalibration wall_camera() {
  SensorCalibration cal;
  cal.depth = {101, 101, 100, 100, 50, 50, {}};
  cal.color = cal.depth;
  cal.depth_scale = 1000;
  cal.min_depth_m = 0.1;
  cal.max_depth_m = 10;
  return cal;
}

Box make_box(const std::string& id, const std::string& label, const Pose& T_world_box, Eigen::Vector3d size) {
  Box b;
  b.id = id;
  b.label = label;
  b.instance = id;
  b.T_world_box = T_world_box;
  b.size = size;
  return b;
}

}  // namespace

TEST_CASE("depth pixels take the label of the box containing their point - the smallest box wins") {
  const SensorCalibration cal = wall_camera();
  cv::Mat depth(101, 101, CV_16UC1, cv::Scalar(2000));
  depth.at<uint16_t>(0, 0) = 0;          // no reading
  depth.at<uint16_t>(100, 100) = 20000;  // 20 m, beyond max_depth_m
  // The same scene seen from an arbitrary camera pose: boxes are placed relative to the camera.
  const Pose T_world_sensor = pose_from_xyz_ypr_deg({3, -2, 1.5, 30, -10, 95});
  auto at = [&](double x, double y, double z) { return T_world_sensor * pose_from_xyz_ypr_deg({x, y, z, 0, 0, 0}); };
  const std::vector<Box> boxes = {make_box("cup_1", "cup", at(0, 0, 2), {0.42, 0.42, 0.2}),
                                  make_box("table_1", "table", at(0.1, 0, 2), {1.02, 1.02, 0.2})};
  const LabelMap map = make_label_map(boxes, {{"table", 5}});
  REQUIRE(map.class_id("cup") == 1);
  REQUIRE(map.class_id("table") == 5);
  const auto ordered = prioritized_boxes(boxes, map);
  REQUIRE(ordered[0].box.id == "cup_1");

  const FrameLabels labels = label_depth_image(depth, cal, make_depth_view(cal.depth), T_world_sensor, ordered);
  // cup: |u - 50| <= 10.5 and |v - 50| <= 10.5 -> 21 x 21; table: u - 50 in [-20.5, 30.5], |v - 50| <= 25.5
  CHECK(labels.boxes[0].labeled_pixels == 21 * 21);
  CHECK(labels.boxes[1].labeled_pixels == 51 * 51 - 21 * 21);
  CHECK(labels.ambiguous_pixels == 21 * 21);
  CHECK(labels.valid_pixels == 101 * 101 - 2);
  CHECK(labels.labeled_pixels == 51 * 51);
  CHECK(labels.class_ids.at<uint16_t>(50, 50) == 1);
  CHECK(labels.class_ids.at<uint16_t>(50, 61) == 5);
  CHECK(labels.class_ids.at<uint16_t>(50, 80) == 5);
  CHECK(labels.class_ids.at<uint16_t>(50, 81) == kUnlabeled);
  CHECK(labels.class_ids.at<uint16_t>(50, 29) == kUnlabeled);
  CHECK(labels.class_ids.at<uint16_t>(0, 0) == kNoDepth);
  CHECK(labels.class_ids.at<uint16_t>(100, 100) == kNoDepth);
  CHECK(labels.instance_ids.at<uint16_t>(50, 50) == map.instance_id("cup_1"));
  CHECK(labels.instance_ids.at<uint16_t>(50, 61) == map.instance_id("table_1"));
}

TEST_CASE("a box behind the camera labels nothing") {
  const SensorCalibration cal = wall_camera();
  cv::Mat depth(101, 101, CV_16UC1, cv::Scalar(2000));
  const std::vector<Box> boxes = {make_box("b", "thing", pose_from_xyz_ypr_deg({0, 0, -2, 0, 0, 0}), {5, 5, 1})};
  const LabelMap map = make_label_map(boxes, {});
  const auto labels =
      label_depth_image(depth, cal, make_depth_view(cal.depth), Pose::Identity(), prioritized_boxes(boxes, map));
  CHECK(labels.labeled_pixels == 0);
}

TEST_CASE("label map: fixed ids kept - others alphabetical in the free ids - instances sorted") {
  const std::vector<Box> boxes = {make_box("z", "monitor", Pose::Identity(), {1, 1, 1}),
                                  make_box("a", "book", Pose::Identity(), {1, 1, 1}),
                                  make_box("m", "desk", Pose::Identity(), {1, 1, 1})};
  const LabelMap map = make_label_map(boxes, {{"book", 1}, {"chair", 3}});
  CHECK(map.class_id("book") == 1);
  CHECK(map.class_id("chair") == 3);
  CHECK(map.class_id("desk") == 2);
  CHECK(map.class_id("monitor") == 4);
  CHECK(map.instance_id("a") == 1);
  CHECK(map.instance_id("m") == 2);
  CHECK(map.instance_id("z") == 3);
  const auto j = to_json(map);
  CHECK(j["no_depth"] == 65535);
  CHECK(j["unlabeled"] == 0);
  CHECK(label_map_from_json(j).class_id("monitor") == 4);
  CHECK_THROWS_AS(make_label_map(boxes, {{"book", 2}, {"desk", 2}}), InputError);
}

TEST_CASE("per box: labeled and covered pixels and the labeled rectangle, by hand") {
  // The cup (0.42 m square, 0.2 m deep at 1.9-2.1 m) on the wall camera: its rays cover pixels
  // with |u - 50| <= 11.05 (the near face, 1.9 m) -> 23 x 23; its points label 21 x 21.
  const SensorCalibration cal = wall_camera();
  const cv::Mat depth(101, 101, CV_16UC1, cv::Scalar(2000));
  const std::vector<Box> boxes = {make_box("cup_1", "cup", pose_from_xyz_ypr_deg({0, 0, 2, 0, 0, 0}), {0.42, 0.42, 0.2}),
                                  make_box("far", "wall", pose_from_xyz_ypr_deg({0, 0, 20, 0, 0, 0}), {1, 1, 1}),
                                  make_box("left", "thing", pose_from_xyz_ypr_deg({-10, 0, 2, 0, 0, 0}), {1, 1, 1})};
  const LabelMap map = make_label_map(boxes, {});
  const auto ordered = prioritized_boxes(boxes, map);
  REQUIRE(ordered[0].box.id == "cup_1");
  const DepthView view = make_depth_view(cal.depth);
  const FrameLabels labels = label_depth_image(depth, cal, view, Pose::Identity(), ordered);
  CHECK(labels.boxes[0].labeled_pixels == 21 * 21);
  CHECK(labels.boxes[0].covered_pixels == 23 * 23);
  CHECK(labels.boxes[0].bbox == cv::Rect(40, 40, 21, 21));
  // Beyond the 10 m range and outside the view: culled, nothing covered.
  CHECK(boxes_in_view(ordered, cal, view, Pose::Identity()) == std::vector<size_t>{0});
  for (size_t k = 1; k < 3; ++k) CHECK(labels.boxes[k].covered_pixels == 0);
}

TEST_CASE("footprints never lose a pixel: labels equal a test of every pixel against every box") {
  // A distorted camera, boxes in many poses (some behind, some straddling the near plane): the
  // footprint-limited labeler must agree with brute force on every pixel.
  SensorCalibration cal;
  cal.depth = {160, 120, 120, 118, 81.5, 58.3, {0.25, -0.9, 0.002, -0.001, 1.1}};
  cal.color = cal.depth;
  cal.depth_scale = 1000;
  cal.min_depth_m = 0.3;
  cal.max_depth_m = 6;
  const DepthView view = make_depth_view(cal.depth);
  cv::RNG rng(11);
  cv::Mat depth(120, 160, CV_16UC1);
  rng.fill(depth, cv::RNG::UNIFORM, 200, 7000);
  std::vector<Box> boxes;
  for (int i = 0; i < 40; ++i)
    boxes.push_back(make_box("b" + std::to_string(i), "c" + std::to_string(i % 5),
                             pose_from_xyz_ypr_deg({rng.uniform(-3.0, 3.0), rng.uniform(-2.0, 2.0), rng.uniform(-1.0, 6.0),
                                                    rng.uniform(-180.0, 180.0), rng.uniform(-90.0, 90.0),
                                                    rng.uniform(-180.0, 180.0)}),
                             {rng.uniform(0.1, 2.0), rng.uniform(0.1, 2.0), rng.uniform(0.1, 2.0)}));
  const LabelMap map = make_label_map(boxes, {});
  const auto ordered = prioritized_boxes(boxes, map);
  const Pose T_world_sensor = pose_from_xyz_ypr_deg({0.2, -0.1, 0.05, 3, -2, 1});
  const FrameLabels labels = label_depth_image(depth, cal, view, T_world_sensor, ordered);
  int mismatches = 0, labeled = 0;
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      const double z = depth.at<uint16_t>(v, u) / cal.depth_scale;
      uint16_t expected = kNoDepth;
      if (z >= cal.min_depth_m && z <= cal.max_depth_m) {
        expected = kUnlabeled;
        const Eigen::Vector2f& r = view.rays[static_cast<size_t>(v) * depth.cols + u];
        const Eigen::Vector3d p = T_world_sensor * Eigen::Vector3d(r.x() * z, r.y() * z, z);
        for (const auto& lb : ordered)
          if (contains(lb.box, p)) {
            expected = lb.class_id;
            break;
          }
      }
      labeled += expected != kNoDepth && expected != kUnlabeled;
      mismatches += labels.class_ids.at<uint16_t>(v, u) != expected;
    }
  CHECK(labeled > 1000);  // the test means something: many pixels are in boxes
  CHECK(mismatches <= 2);  // float against double on a box face, at most
}
