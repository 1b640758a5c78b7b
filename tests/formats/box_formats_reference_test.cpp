// Each tool's own files, hand-written in tests/formats/tool_examples/ from the tools' documented
// layouts (the labelCloud ones by make_labelcloud_examples.py), read and compared to the boxes
// they were made from: centre, size and rotation to 1e-9, class and instance.
#include <catch2/catch.hpp>

#include "olt/core/fs.h"
#include "olt/formats/box_formats.h"

using namespace olt;

namespace {

std::string example(const std::string& name) {
  return read_file(std::string(OLT_SOURCE_DIR) + "/tests/formats/tool_examples/" + name);
}

Eigen::Matrix3d about(const Eigen::Vector3d& axis, double radians) {
  return Eigen::AngleAxisd(radians, axis).toRotationMatrix();
}
const Eigen::Vector3d kX = Eigen::Vector3d::UnitX(), kY = Eigen::Vector3d::UnitY(), kZ = Eigen::Vector3d::UnitZ();

struct KnownBox {
  std::string label, instance;
  Eigen::Vector3d center, size;
  Eigen::Matrix3d rotation;
};

void check_boxes(const std::vector<Box>& boxes, const std::vector<KnownBox>& known) {
  REQUIRE(boxes.size() == known.size());
  for (size_t i = 0; i < known.size(); ++i) {
    INFO("box " << i << " (" << known[i].label << ")");
    CHECK(boxes[i].label == known[i].label);
    CHECK(boxes[i].instance == known[i].instance);
    CHECK((boxes[i].T_world_box.translation() - known[i].center).norm() < 1e-9);
    CHECK((boxes[i].size - known[i].size).norm() < 1e-9);
    CHECK((boxes[i].T_world_box.linear() - known[i].rotation).norm() < 1e-9);
  }
}

// SUSTechPOINTS: R = Rx·Ry·Rz (three.js Euler "XYZ"), radians, not normalised.
Eigen::Matrix3d three_js_xyz(double x, double y, double z) { return about(kX, x) * about(kY, y) * about(kZ, z); }

// The three boxes of make_labelcloud_examples.py; labelCloud: R = Rz·Ry·Rx, degrees.
std::vector<KnownBox> labelcloud_boxes() {
  const auto zyx_deg = [](double x, double y, double z) {
    return Eigen::Matrix3d(about(kZ, z * M_PI / 180) * about(kY, y * M_PI / 180) * about(kX, x * M_PI / 180));
  };
  return {{"chair", "chair_0", {1.25, -0.5, 0.45}, {0.6, 0.55, 0.9}, zyx_deg(0, 0, 330)},
          {"table", "table_1", {0.0, 1.5, 0.375}, {1.6, 0.8, 0.75}, zyx_deg(355, 10, 90)},
          {"lamp", "lamp_2", {-1.0, -1.0, 1.2}, {0.3, 0.25, 0.5}, zyx_deg(12.5, 0, 47.25)}};
}

}  // namespace

TEST_CASE("SUSTechPOINTS reference frame: a bare array as its app writes it - obj_id is the instance") {
  const BoxFile read = read_box_file("sustechpoints", "000950.json", example("sustechpoints_000950.json"));
  CHECK(read.warnings.empty());
  check_boxes(read.boxes, {{"Car", "1", {10.5, -3.25, -0.8}, {4.2, 1.8, 1.5}, three_js_xyz(0, 0, 4.45)},
                           {"Pedestrian", "2", {3.0, 2.5, -0.6}, {0.6, 0.7, 1.7}, three_js_xyz(0, 0, -3.13)},
                           {"Truck", "7", {-12.0, 8.0, 0.3}, {9.0, 2.6, 3.4}, three_js_xyz(0.02, -0.05, 1.2)},
                           // obj_id "" (none): the box is its own instance
                           {"Car", "Car_3", {20.0, 0.5, -0.7}, {4.5, 1.9, 1.6}, three_js_xyz(0, 0, 0)}});
}

TEST_CASE("SUSTechPOINTS: boxes of one obj_id in a file are one instance - in both layouts") {
  const std::string objects = R"([
    {"obj_type": "Car", "obj_id": "5", "psr": {"position": {"x": 0, "y": 0, "z": 0},
      "scale": {"x": 4, "y": 2, "z": 1}, "rotation": {"x": 0, "y": 0, "z": 0}}},
    {"obj_type": "Car", "obj_id": "5", "obj_attr": "static", "psr": {"position": {"x": 4, "y": 0, "z": 0},
      "scale": {"x": 4, "y": 2, "z": 1}, "rotation": {"x": 0, "y": 0, "z": 0}}}])";
  for (const std::string& text : {objects, R"({"frame": "000001", "scene": "s", "objs": )" + objects + "}"}) {
    const auto boxes = read_boxes("sustechpoints", "f.json", text);
    REQUIRE(boxes.size() == 2);
    CHECK(boxes[0].instance == "5");
    CHECK(boxes[1].instance == "5");
    CHECK(boxes[0].id != boxes[1].id);
  }
}

TEST_CASE("labelCloud reference files: centroid_abs (degrees) - centroid_rel (radians) - vertices give the boxes") {
  for (const auto& [format, file] :
       std::vector<std::pair<std::string, std::string>>{{"labelcloud", "labelcloud_centroid_abs.json"},
                                                        {"labelcloud_rel", "labelcloud_centroid_rel.json"},
                                                        {"labelcloud_vertices", "labelcloud_vertices.json"}}) {
    INFO("format " << format << ", file " << file);
    const BoxFile read = read_box_file(format, file, example(file));
    CHECK(read.warnings.empty());
    check_boxes(read.boxes, labelcloud_boxes());
  }
}
