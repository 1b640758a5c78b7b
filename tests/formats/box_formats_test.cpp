// Each annotation tool's convention, checked on boxes whose corners are computed by hand, and
// native -> tool -> native round trips.
#include "olt/formats/box_formats.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"

using namespace olt;

namespace {

// Corner 7 is the box's local (+x, +y, +z) corner, i.e. (+size/2) rotated and moved.
Eigen::Vector3d corner7(const Box& b) { return box_corners(b)[7]; }

}  // namespace

TEST_CASE("labelCloud: degrees - length/width/height along x/y/z - R = Rz Ry Rx") {
  const auto boxes = read_boxes("labelcloud", "lc.json", R"({"folder": "pointclouds", "filename": "a.pcd",
    "path": "pointclouds/a.pcd", "objects": [
      {"name": "car", "centroid": {"x": 1, "y": 2, "z": 3}, "dimensions": {"length": 4, "width": 2, "height": 1},
       "rotations": {"x": 0, "y": 0, "z": 90}},
      {"name": "cup", "centroid": {"x": 0, "y": 0, "z": 0}, "dimensions": {"length": 4, "width": 2, "height": 1},
       "rotations": {"x": 90, "y": 0, "z": 90}}]})");
  REQUIRE(boxes.size() == 2);
  CHECK(boxes[0].label == "car");
  CHECK(boxes[0].instance == "car_0");
  // yaw 90: local (-2, -1, -0.5) -> (1, -2, -0.5), plus the centre
  CHECK(box_corners(boxes[0])[0].isApprox(Eigen::Vector3d(2, 0, 2.5), 1e-12));
  CHECK(corner7(boxes[0]).isApprox(Eigen::Vector3d(0, 4, 3.5), 1e-12));
  // x first: (2, 1, 0.5) -Rx(90)-> (2, -0.5, 1) -Rz(90)-> (0.5, 2, 1)
  CHECK(corner7(boxes[1]).isApprox(Eigen::Vector3d(0.5, 2, 1), 1e-12));
  const auto radians = read_boxes("labelcloud_rel", "lc.json", R"({"objects": [{"name": "cup",
    "centroid": {"x": 0, "y": 0, "z": 0}, "dimensions": {"length": 4, "width": 2, "height": 1},
    "rotations": {"x": 1.5707963267948966, "y": 0, "z": 1.5707963267948966}}]})");
  CHECK(corner7(radians[0]).isApprox(Eigen::Vector3d(0.5, 2, 1), 1e-12));
}

TEST_CASE("SUSTechPOINTS: radians - three.js XYZ order R = Rx Ry Rz - obj_id is the instance") {
  const std::string object = R"({"obj_type": "Car", "obj_id": "7", "psr": {"position": {"x": 0, "y": 0, "z": 0},
    "scale": {"x": 4, "y": 2, "z": 1}, "rotation": {"x": 1.5707963267948966, "y": 0, "z": 1.5707963267948966}}})";
  for (const std::string& text : {"[" + object + "]", R"({"objs": [)" + object + "]}"}) {
    const auto boxes = read_boxes("sustechpoints", "frame.json", text);
    REQUIRE(boxes.size() == 1);
    CHECK(boxes[0].label == "Car");
    CHECK(boxes[0].instance == "7");
    // z first: (2, 1, 0.5) -Rz(90)-> (-1, 2, 0.5) -Rx(90)-> (-1, -0.5, 2)
    CHECK(corner7(boxes[0]).isApprox(Eigen::Vector3d(-1, -0.5, 2), 1e-12));
  }
}

TEST_CASE("Supervisely: figures of cuboid_3d - objectKey is the instance - R = Rx Ry Rz") {
  const auto boxes = read_boxes("supervisely", "a.pcd.json", R"({"description": "", "key": "k", "tags": [],
    "objects": [{"key": "obj1", "classTitle": "chair", "tags": []}],
    "figures": [
      {"key": "f1", "objectKey": "obj1", "geometryType": "cuboid_3d", "geometry": {
        "position": {"x": 1, "y": 1, "z": 1}, "rotation": {"x": 1.5707963267948966, "y": 0, "z": 1.5707963267948966},
        "dimensions": {"x": 4, "y": 2, "z": 1}}},
      {"key": "f2", "objectKey": "obj1", "geometryType": "point", "geometry": {}}]})");
  REQUIRE(boxes.size() == 1);
  CHECK(boxes[0].id == "f1");
  CHECK(boxes[0].label == "chair");
  CHECK(boxes[0].instance == "obj1");
  CHECK(corner7(boxes[0]).isApprox(Eigen::Vector3d(0, 0.5, 3), 1e-12));
}

TEST_CASE("native -> tool -> native keeps every corner - class and - where the tool has them - instances") {
  std::vector<Box> boxes;
  const double angles[][3] = {{10, -20, 30}, {175, 5, -60}, {-90, 45, 10}};
  for (int i = 0; i < 3; ++i) {
    Box b;
    b.id = "b" + std::to_string(i);
    b.label = i == 1 ? "book" : "mug";
    b.instance = b.label + "_1";  // boxes 0 and 2 make one instance
    b.size = Eigen::Vector3d(0.3 + i, 0.2, 0.1 + 0.05 * i);
    b.T_world_box = pose_from_xyz_ypr_deg({1.0 * i, -2, 0.5, angles[i][0], angles[i][1], angles[i][2]});
    boxes.push_back(b);
  }
  for (const auto& format : box_formats()) {
    INFO("format " << format);
    const auto back = read_boxes(format, "x.json", write_boxes(format, boxes));
    REQUIRE(back.size() == boxes.size());
    for (size_t i = 0; i < boxes.size(); ++i) {
      for (int c = 0; c < 8; ++c) CHECK(box_corners(back[i])[c].isApprox(box_corners(boxes[i])[c], 1e-9));
      CHECK(back[i].label == boxes[i].label);
      if (format == "sustechpoints" || format == "supervisely" || format == "native")
        CHECK(back[i].instance == boxes[i].instance);
    }
  }
}

TEST_CASE("tool errors name the file - the line and the field") {
  CHECK_THROWS_WITH(
      read_boxes("sustechpoints", "f.json",
                 "[{\"obj_type\": \"Car\",\n \"psr\": {\"position\": {\"x\": 0, \"y\": 0, \"z\": 0},\n \"scale\": "
                 "{\"x\": 1, \"y\": -1, \"z\": 1}, \"rotation\": {\"x\": 0, \"y\": 0, \"z\": 0}}}]"),
      Catch::Contains("f.json:1:") && Catch::Contains("size along y must be > 0"));
  CHECK_THROWS_WITH(
      read_boxes("labelcloud", "l.json",
                 "{\"objects\": [{\"name\": \"a\",\n \"centroid\": {\"x\": 0, \"y\": \"no\", \"z\": 0}}]}"),
      Catch::Contains("l.json:2:") && Catch::Contains("centroid.y: expected a finite number"));
  CHECK_THROWS_AS(
      read_boxes("supervisely", "s.json",
                 "{\"objects\": [], \"figures\": [{\"objectKey\": \"zz\", \"geometryType\": \"cuboid_3d\"}]}"),
      InputError);
  // Two figures of one key: a box's id names it in every frame's files.
  const std::string figure =
      R"({"key": "f1", "objectKey": "o", "geometryType": "cuboid_3d", "geometry": {"position": {"x": 0, "y": 0,
      "z": 0}, "rotation": {"x": 0, "y": 0, "z": 0}, "dimensions": {"x": 1, "y": 1, "z": 1}}})";
  CHECK_THROWS_WITH(
      read_boxes("supervisely", "d.json",
                 R"({"objects": [{"key": "o", "classTitle": "chair"}], "figures": [)" + figure + "," + figure + "]}"),
      Catch::Contains("d.json:2:") && Catch::Contains("figures[1]: id 'f1' is also figures[0]'s"));
}

TEST_CASE("label map renames classes and the ignore list drops boxes") {
  std::vector<Box> boxes(3);
  boxes[0].label = "Car";
  boxes[1].label = "DontCare";
  boxes[2].label = "Pedestrian";
  const auto mapped = map_labels(boxes, {{"Car", "vehicle"}}, {"DontCare"});
  REQUIRE(mapped.size() == 2);
  CHECK(mapped[0].label == "vehicle");
  CHECK(mapped[1].label == "Pedestrian");
}
