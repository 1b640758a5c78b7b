#include "olt/propagate/propagate.h"

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "olt/core/error.h"
#include "olt/propagate/visibility.h"

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

// Pixels whose ray meets the box between the camera's depth limits, counted per row from the first
// such pixel to the last (as the labeler counts them), tested in double precision on every pixel.
int covered_by_rays(const DepthView& view, const SensorCalibration& cal, const Pose& T_world_sensor, const Box& box) {
  const Pose T_box_sensor = box.T_world_box.inverse() * T_world_sensor;
  int covered = 0;
  for (int v = 0; v < view.height; ++v) {
    int first = -1, last = -1;
    for (int u = 0; u < view.width; ++u) {
      const Eigen::Vector2f& r = view.rays[static_cast<size_t>(v) * view.width + u];
      const Eigen::Vector3d direction = T_box_sensor.linear() * Eigen::Vector3d(r.x(), r.y(), 1);
      const Eigen::Vector3d origin = T_box_sensor.translation();
      double enter = cal.min_depth_m, exit = cal.max_depth_m;
      for (int i = 0; i < 3; ++i) {
        const double a = (-0.5 * box.size[i] - origin[i]) / direction[i],
                     b = (0.5 * box.size[i] - origin[i]) / direction[i];
        enter = std::max(enter, std::min(a, b));
        exit = std::min(exit, std::max(a, b));
      }
      if (enter <= exit) {
        if (first < 0) first = u;
        last = u;
      }
    }
    if (first >= 0) covered += last - first + 1;
  }
  return covered;
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
  const std::vector<Box> boxes = {
      make_box("cup_1", "cup", pose_from_xyz_ypr_deg({0, 0, 2, 0, 0, 0}), {0.42, 0.42, 0.2}),
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

TEST_CASE("the depth range's limits are inside it, a unit beyond them is no depth") {
  // wall_camera: 0.1-10 m at 1000 units per metre, so raw 100 and 10000 are the limits.
  const SensorCalibration cal = wall_camera();
  cv::Mat depth(101, 101, CV_16UC1, cv::Scalar(2000));
  depth.at<uint16_t>(0, 0) = 99, depth.at<uint16_t>(0, 1) = 100;
  depth.at<uint16_t>(0, 2) = 10000, depth.at<uint16_t>(0, 3) = 10001, depth.at<uint16_t>(0, 4) = 0;
  const FrameLabels labels = label_depth_image(depth, cal, make_depth_view(cal.depth), Pose::Identity(), {});
  CHECK(labels.valid_pixels == 101 * 101 - 3);
  const std::vector<uint16_t> expected = {kNoDepth, kUnlabeled, kUnlabeled, kNoDepth, kNoDepth};
  for (int u = 0; u < 5; ++u) CHECK(labels.class_ids.at<uint16_t>(0, u) == expected[u]);
}

TEST_CASE("depth range limits between whole raw values, or not a number") {
  SensorCalibration cal = wall_camera();
  cal.min_depth_m = 0.1005, cal.max_depth_m = 9.9995;  // raw 100.5 and 9999.5
  cv::Mat depth(101, 101, CV_16UC1, cv::Scalar(2000));
  depth.at<uint16_t>(0, 0) = 100, depth.at<uint16_t>(0, 1) = 101;
  depth.at<uint16_t>(0, 2) = 9999, depth.at<uint16_t>(0, 3) = 10000;
  const DepthView view = make_depth_view(cal.depth);
  const FrameLabels labels = label_depth_image(depth, cal, view, Pose::Identity(), {});
  const std::vector<uint16_t> expected = {kNoDepth, kUnlabeled, kUnlabeled, kNoDepth};
  for (int u = 0; u < 4; ++u) CHECK(labels.class_ids.at<uint16_t>(0, u) == expected[u]);
  cal.max_depth_m = std::nan("");
  CHECK(label_depth_image(depth, cal, view, Pose::Identity(), {}).valid_pixels == 0);
}

TEST_CASE("footprints never lose a pixel: labels equal a test of every pixel against every box") {
  // A distorted camera and a plain one, boxes in many poses (some behind, some straddling the near
  // plane): the footprint-limited labeler must agree with brute force on every pixel.
  SensorCalibration cal;
  cal.depth = {160, 120, 120, 118, 81.5, 58.3, {0.25, -0.9, 0.002, -0.001, 1.1}};
  SECTION("plain pinhole") { cal.depth.distortion = {}; }
  SECTION("strong distortion") {}
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
    boxes.push_back(make_box(
        "b" + std::to_string(i), "c" + std::to_string(i % 5),
        pose_from_xyz_ypr_deg({rng.uniform(-3.0, 3.0), rng.uniform(-2.0, 2.0), rng.uniform(-1.0, 6.0),
                               rng.uniform(-180.0, 180.0), rng.uniform(-90.0, 90.0), rng.uniform(-180.0, 180.0)}),
        {rng.uniform(0.1, 2.0), rng.uniform(0.1, 2.0), rng.uniform(0.1, 2.0)}));
  const LabelMap map = make_label_map(boxes, {});
  const auto ordered = prioritized_boxes(boxes, map);
  const Pose T_world_sensor = pose_from_xyz_ypr_deg({0.2, -0.1, 0.05, 3, -2, 1});
  const FrameLabels labels = label_depth_image(depth, cal, view, T_world_sensor, ordered);
  int mismatches = 0, labeled = 0, ambiguous = 0;
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      const double z = depth.at<uint16_t>(v, u) / cal.depth_scale;
      uint16_t expected = kNoDepth;
      if (z >= cal.min_depth_m && z <= cal.max_depth_m) {
        expected = kUnlabeled;
        const Eigen::Vector2f& r = view.rays[static_cast<size_t>(v) * depth.cols + u];
        const Eigen::Vector3d p = T_world_sensor * Eigen::Vector3d(r.x() * z, r.y() * z, z);
        int holders = 0;
        for (const auto& lb : ordered)
          if (contains(lb.box, p) && holders++ == 0) expected = lb.class_id;
        ambiguous += holders > 1;
      }
      labeled += expected != kNoDepth && expected != kUnlabeled;
      mismatches += labels.class_ids.at<uint16_t>(v, u) != expected;
    }
  CHECK(labeled > 1000);   // the test means something: many pixels are in boxes
  CHECK(mismatches <= 2);  // float against double on a box face, at most
  CHECK(std::abs(ambiguous - labels.ambiguous_pixels) <= 2);
  CHECK(ambiguous > 100);
  // Each box's figures are those of the pixels carrying its instance (ids are one per box here).
  int labeled_by_boxes = 0;
  for (size_t k = 0; k < ordered.size(); ++k) {
    const cv::Mat mine = labels.instance_ids == ordered[k].instance_id;
    CHECK(labels.boxes[k].labeled_pixels == cv::countNonZero(mine));
    CHECK(labels.boxes[k].bbox == cv::boundingRect(mine));
    CHECK(std::abs(labels.boxes[k].covered_pixels - covered_by_rays(view, cal, T_world_sensor, ordered[k].box)) <= 2);
    labeled_by_boxes += labels.boxes[k].labeled_pixels;
  }
  CHECK(labeled_by_boxes == labels.labeled_pixels);
}

TEST_CASE("labels at colour resolution: a shifted finer colour camera sees what is in front") {
  // Depth camera: the 101x101 wall camera (wall at 2 m) with a 0.1 m patch at 1 m in front of it.
  // Colour camera: 5 cm to the left of it, 201x201 at twice the focal length.
  SensorCalibration cal = wall_camera();
  cal.color = {201, 201, 200, 200, 100, 100, {}};
  cal.T_color_depth = pose_from_xyz_ypr_deg({0.05, 0, 0, 0, 0, 0});
  cv::Mat depth(101, 101, CV_16UC1, cv::Scalar(2000));
  depth(cv::Rect(45, 45, 11, 11)).setTo(1000);  // |u - 50| <= 5 at 1 m: x within +-0.05 m
  const std::vector<Box> boxes = {
      make_box("cup_1", "cup", pose_from_xyz_ypr_deg({0.3, 0, 2, 0, 0, 0}), {0.42, 0.42, 0.2}),
      make_box("patch_1", "patch", pose_from_xyz_ypr_deg({0, 0, 1, 0, 0, 0}), {0.12, 0.12, 0.1})};
  const LabelMap map = make_label_map(boxes, {});
  const DepthView view = make_depth_view(cal.depth);
  const FrameLabels labels = label_depth_image(depth, cal, view, Pose::Identity(), prioritized_boxes(boxes, map));
  const uint16_t cup = map.class_id("cup"), patch = map.class_id("patch");

  // The exact answer per colour pixel: its ray (in the depth frame it starts at x = -0.05) meets the
  // patch, or the wall; nullopt where the depth camera cannot see that wall point (outside its view,
  // or hidden behind the patch).
  auto truth = [&](int cu, int cv_) -> std::optional<uint16_t> {
    const double x = (cu - 100) / 200.0, y = (cv_ - 100) / 200.0;
    const double px = -0.05 + x * 1.0, py = y * 1.0;  // at z = 1 m, depth frame
    if (std::abs(px) <= 0.05 && std::abs(py) <= 0.05) return patch;
    const double wx = -0.05 + x * 2.0, wy = y * 2.0;                                  // at z = 2 m
    if (std::abs(wx) > 0.98 || std::abs(wy) > 0.98) return std::nullopt;              // depth view's edge
    if (std::abs(wx / 2) <= 0.056 && std::abs(wy / 2) <= 0.056) return std::nullopt;  // hidden by the patch
    if (std::abs(wx - 0.3) <= 0.21 && std::abs(wy) <= 0.21) return cup;
    return kUnlabeled;
  };
  auto agreement = [&](const ColorLabels& c, int* no_depth) {
    int checked = 0, agree = 0;
    *no_depth = 0;
    for (int v = 0; v < 201; ++v)
      for (int u = 0; u < 201; ++u) {
        const auto expected = truth(u, v);
        if (!expected) continue;
        ++checked;
        const uint16_t got = c.class_ids.at<uint16_t>(v, u);
        *no_depth += got == kNoDepth;
        agree += got == *expected;
      }
    return static_cast<double>(agree) / checked;
  };
  int holes = 0;
  // One depth point per 2x2 colour pixels: without filling, most colour pixels get none.
  const ColorLabels sparse = label_color_image(labels, depth, cal, view, 0, 0.05);
  CHECK(sparse.class_ids.size() == cv::Size(201, 201));
  agreement(sparse, &holes);
  CHECK(holes > 201 * 201 / 2);
  // Filled from neighbours within 2 pixels on the front surface: right nearly everywhere, and the
  // patch (in front) wins over the wall behind it.
  const ColorLabels filled = label_color_image(labels, depth, cal, view, 2, 0.05);
  CHECK(agreement(filled, &holes) > 0.99);
  CHECK(holes == 0);
  CHECK(filled.class_ids.at<uint16_t>(100, 110) == patch);  // the patch's centre: x = 0.05 from the colour camera
  CHECK(filled.class_ids.at<uint16_t>(100, 135) == cup);    // the cup's centre: x = 0.35 / 2
  // The same camera for depth and colour (registered depth): the depth labels themselves.
  SensorCalibration registered = wall_camera();
  const ColorLabels same = label_color_image(labels, depth, registered, view, 2, 0.05);
  CHECK(cv::norm(same.class_ids, labels.class_ids, cv::NORM_INF) == 0);
}

TEST_CASE("an explicit priority beats the smaller volume - a margin keeps the surface under a box unlabeled") {
  const SensorCalibration cal = wall_camera();
  const cv::Mat depth(101, 101, CV_16UC1, cv::Scalar(2000));
  const DepthView view = make_depth_view(cal.depth);
  std::vector<Box> boxes = {
      make_box("cup_1", "cup", pose_from_xyz_ypr_deg({0, 0, 2, 0, 0, 0}), {0.42, 0.42, 0.2}),
      make_box("table_1", "table", pose_from_xyz_ypr_deg({0.1, 0, 2, 0, 0, 0}), {1.02, 1.02, 0.2})};
  boxes[1].priority = 1;
  LabelMap map = make_label_map(boxes, {});
  FrameLabels labels = label_depth_image(depth, cal, view, Pose::Identity(), prioritized_boxes(boxes, map));
  CHECK(labels.class_ids.at<uint16_t>(50, 50) == map.class_id("table"));  // inside both: the table wins now
  CHECK(labels.boxes[0].labeled_pixels == 51 * 51);
  CHECK(labels.boxes[1].labeled_pixels == 0);

  // A box from 1.95 to 2.15 m whose bottom face (its -z side) is nearest the camera: the wall at 2 m
  // is 5 cm above that face. A 4 cm margin keeps it; a 10 cm margin leaves it out.
  Box on_wall = make_box("rug_1", "rug", pose_from_xyz_ypr_deg({0, 0, 2.05, 0, 0, 0}), {0.42, 0.42, 0.2});
  map = make_label_map({on_wall}, {});
  on_wall.margin_m = 0.04;
  CHECK(label_depth_image(depth, cal, view, Pose::Identity(), prioritized_boxes({on_wall}, map)).labeled_pixels ==
        21 * 21);
  on_wall.margin_m = 0.1;
  CHECK(label_depth_image(depth, cal, view, Pose::Identity(), prioritized_boxes({on_wall}, map)).labeled_pixels == 0);
}

TEST_CASE("depth views are made once per camera in a process - the same rays as made afresh, another camera its own") {
  Intrinsics camera;
  camera.width = 64, camera.height = 48, camera.fx = 50, camera.fy = 51, camera.cx = 31.5, camera.cy = 23.5;
  camera.distortion = {0.1, -0.05, 0.001, 0.002, 0.0};
  const auto first = shared_depth_view(camera);
  CHECK(shared_depth_view(camera) == first);
  CHECK(first->rays == make_depth_view(camera).rays);
  Intrinsics other = camera;
  other.fx = 52;
  const auto second = shared_depth_view(other);
  CHECK(second != first);
  CHECK(second->rays == make_depth_view(other).rays);
}
