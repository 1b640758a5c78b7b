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

  const FrameLabels labels = label_depth_image(depth, cal, pixel_rays(cal.depth), T_world_sensor, ordered);
  // cup: |u - 50| <= 10.5 and |v - 50| <= 10.5 -> 21 x 21; table: u - 50 in [-20.5, 30.5], |v - 50| <= 25.5
  CHECK(labels.box_pixels[0] == 21 * 21);
  CHECK(labels.box_pixels[1] == 51 * 51 - 21 * 21);
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
      label_depth_image(depth, cal, pixel_rays(cal.depth), Pose::Identity(), prioritized_boxes(boxes, map));
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
