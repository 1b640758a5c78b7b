// What OLT writes for each tool, read by that tool's own rules, re-implemented here from its
// source (no tool code): SUSTechPOINTS's web app (annotation.js: a bare array, `annotations.map`)
// and label checker (tools/check_labels.py: no obj_id twice in a frame); labelCloud's import
// (io/labels/centroid.py reads centroid, dimensions and rotations by `.values()`, i.e. by key order;
// io/labels/vertices.py and utils/math3d.py vertices2rotations).
#include <catch2/catch.hpp>
#include <map>

#include "olt/core/error.h"
#include "olt/formats/box_formats.h"

using namespace olt;
using ordered = nlohmann::ordered_json;

namespace {

Eigen::Matrix3d about(const Eigen::Vector3d& axis, double radians) {
  return Eigen::AngleAxisd(radians, axis).toRotationMatrix();
}
const Eigen::Vector3d kX = Eigen::Vector3d::UnitX(), kY = Eigen::Vector3d::UnitY(), kZ = Eigen::Vector3d::UnitZ();
double radians(double degrees) { return degrees * M_PI / 180; }

// labelCloud's vertex k has these local signs of (length, width, height).
const int kLabelCloudSigns[8][3] = {{-1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {1, -1, -1},
                                    {-1, -1, 1},  {-1, 1, 1},  {1, 1, 1},  {1, -1, 1}};

// OLT's corner with the same local signs (x: bit 0, y: bit 1, z: bit 2).
Eigen::Vector3d olt_corner(const Box& b, const int sign[3]) {
  return box_corners(b)[(sign[0] > 0 ? 1 : 0) + (sign[1] > 0 ? 2 : 0) + (sign[2] > 0 ? 4 : 0)];
}

// Boxes turned every way, including angles that come out negative or near 360 degrees; two
// instances of several boxes, and an instance whose name is another's "<name>-2".
std::vector<Box> test_boxes() {
  const double ypr_deg[][3] = {{10, -20, 30}, {175, 5, -60}, {-90, 45, 10}, {-0.5, 0, 0}, {0, 0, 180}};
  const char* instances[] = {"mug", "mug", "mug-2", "mug", "shelf_1"};
  std::vector<Box> boxes;
  for (int i = 0; i < 5; ++i) {
    Box b;
    b.id = "b" + std::to_string(i);
    b.label = i == 4 ? "shelf" : "mug";
    b.instance = instances[i];
    b.size = Eigen::Vector3d(0.3 + i, 0.2, 0.1 + 0.05 * i);
    b.T_world_box = pose_from_xyz_ypr_deg({1.0 * i, -2, 0.5, ypr_deg[i][0], ypr_deg[i][1], ypr_deg[i][2]});
    boxes.push_back(b);
  }
  return boxes;
}

Eigen::Vector3d xyz(const nlohmann::json& v) {
  return {v.at("x").get<double>(), v.at("y").get<double>(), v.at("z").get<double>()};
}

// The first three values of a JSON object in file order, as Python's list(d.values()).
Eigen::Vector3d values_in_order(const ordered& object) {
  std::vector<double> v;
  for (const auto& item : object.items()) v.push_back(item.value().get<double>());
  REQUIRE(v.size() == 3);
  return {v[0], v[1], v[2]};
}

std::vector<std::string> keys_in_order(const ordered& object) {
  std::vector<std::string> keys;
  for (const auto& item : object.items()) keys.push_back(item.key());
  return keys;
}

// A labelCloud box (centroid, dimensions, rotations in degrees) as labelCloud rotates it:
// v' = Rz·Ry·Rx·v about the centroid.
Eigen::Vector3d labelcloud_vertex(const Eigen::Vector3d& c, const Eigen::Vector3d& d, const Eigen::Vector3d& r_deg,
                                  int k) {
  const Eigen::Vector3d local(kLabelCloudSigns[k][0] * d[0] / 2, kLabelCloudSigns[k][1] * d[1] / 2,
                              kLabelCloudSigns[k][2] * d[2] / 2);
  return c + about(kZ, radians(r_deg[2])) * about(kY, radians(r_deg[1])) * about(kX, radians(r_deg[0])) * local;
}

}  // namespace

TEST_CASE("SUSTechPOINTS as its app and check_labels.py read what OLT writes: a bare array - unique obj_ids") {
  const std::vector<Box> boxes = test_boxes();
  const std::string text = write_boxes("sustechpoints", boxes);
  const nlohmann::json frame = nlohmann::json::parse(text);
  REQUIRE(frame.is_array());  // the app runs annotations.map(...) on it
  REQUIRE(frame.size() == boxes.size());
  std::map<std::string, int> seen;  // check_frame_duplicate_id
  std::vector<std::string> ids;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const nlohmann::json& o = frame[i];
    REQUIRE(o.at("obj_type").is_string());
    REQUIRE(o.at("obj_id").is_string());  // String(box.obj_id); "" would be "id absent"
    CHECK(!o.at("obj_id").get<std::string>().empty());
    ids.push_back(o.at("obj_id"));
    ++seen[o.at("obj_id")];
    // createCuboid: position, scale, then rotation as a three.js Euler "XYZ": R = Rx·Ry·Rz
    const Eigen::Vector3d p = xyz(o.at("psr").at("position")), s = xyz(o.at("psr").at("scale")),
                          r = xyz(o.at("psr").at("rotation"));
    const Eigen::Matrix3d R = about(kX, r.x()) * about(kY, r.y()) * about(kZ, r.z());
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d local((c & 1 ? 0.5 : -0.5) * s.x(), (c & 2 ? 0.5 : -0.5) * s.y(),
                                  (c & 4 ? 0.5 : -0.5) * s.z());
      CHECK((p + R * local - box_corners(boxes[i])[c]).norm() < 1e-9);
    }
  }
  for (const auto& [id, count] : seen) CHECK(count == 1);
  // The first box of an instance keeps its name; later ones are numbered, past the taken "mug-2".
  CHECK(ids == std::vector<std::string>{"mug", "mug-3", "mug-2", "mug-4", "shelf_1"});
  CHECK(frame[1].at("obj_attr") == "olt_instance=mug");
  CHECK(frame[0].at("obj_attr") == "");
  // ... and OLT reads the instances back from obj_attr
  const auto back = read_boxes("sustechpoints", "f.json", text);
  for (size_t i = 0; i < boxes.size(); ++i) CHECK(back[i].instance == boxes[i].instance);
}

TEST_CASE("SUSTechPOINTS: olt_instance is found among attributes added in the tool - a ',' in a name is refused") {
  const std::string psr = R"("psr": {"position": {"x": 0, "y": 0, "z": 0}, "scale": {"x": 1, "y": 1, "z": 1},
    "rotation": {"x": 0, "y": 0, "z": 0}})";
  const auto boxes =
      read_boxes("sustechpoints", "f.json",
                 R"([{"obj_type": "Car", "obj_id": "3", "obj_attr": "static, olt_instance=car_1 ,occluded", )" + psr +
                     R"(}, {"obj_type": "Car", "obj_id": "4", "obj_attr": "static", )" + psr + "}]");
  CHECK(boxes[0].instance == "car_1");
  CHECK(boxes[1].instance == "4");
  std::vector<Box> named(2);
  named[0].id = "a", named[1].id = "b";
  named[0].instance = named[1].instance = "left,right";
  CHECK_THROWS_WITH(write_boxes("sustechpoints", named), Catch::Contains("'left,right'") && Catch::Contains("','"));
}

TEST_CASE("labelCloud's centroid import reads what OLT writes: key order - degrees from 0 to 360 - radians within pi") {
  const std::vector<Box> boxes = test_boxes();
  for (const bool relative : {false, true}) {
    INFO((relative ? "centroid_rel" : "centroid_abs"));
    const ordered file = ordered::parse(write_boxes(relative ? "labelcloud_rel" : "labelcloud", boxes));
    CHECK(keys_in_order(file) == std::vector<std::string>{"folder", "filename", "path", "objects"});
    REQUIRE(file.at("objects").size() == boxes.size());
    for (size_t i = 0; i < boxes.size(); ++i) {
      const ordered& o = file.at("objects")[i];
      CHECK(o.at("name") == boxes[i].label);
      CHECK(keys_in_order(o.at("centroid")) == std::vector<std::string>{"x", "y", "z"});
      CHECK(keys_in_order(o.at("dimensions")) == std::vector<std::string>{"length", "width", "height"});
      CHECK(keys_in_order(o.at("rotations")) == std::vector<std::string>{"x", "y", "z"});
      // import: BBox(*centroid.values(), *dimensions.values()); set_rotations(*rotations.values())
      const Eigen::Vector3d c = values_in_order(o.at("centroid")), d = values_in_order(o.at("dimensions"));
      Eigen::Vector3d r = values_in_order(o.at("rotations"));
      for (int k = 0; k < 3; ++k) {
        if (relative) {
          CHECK(r[k] > -M_PI);
          CHECK(r[k] <= M_PI);
          r[k] = r[k] * 180 / M_PI + (r[k] < 0 ? 360 : 0);  // rel2abs_rotation
        } else {
          CHECK(r[k] >= 0);
          CHECK(r[k] < 360);
        }
      }
      for (int k = 0; k < 8; ++k)
        CHECK((labelcloud_vertex(c, d, r, k) - olt_corner(boxes[i], kLabelCloudSigns[k])).norm() < 1e-9);
    }
  }
}

TEST_CASE("labelCloud's vertices import reads what OLT writes: centroid - dimensions - vertices2rotations") {
  const std::vector<Box> boxes = test_boxes();
  const ordered file = ordered::parse(write_boxes("labelcloud_vertices", boxes));
  REQUIRE(file.at("objects").size() == boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) {
    INFO("box " << i);
    const ordered& o = file.at("objects")[i];
    CHECK(o.at("name") == boxes[i].label);
    REQUIRE(o.at("vertices").size() == 8);
    std::vector<Eigen::Vector3d> v;
    for (const auto& p : o.at("vertices")) v.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    for (int k = 0; k < 8; ++k) CHECK((v[k] - olt_corner(boxes[i], kLabelCloudSigns[k])).norm() < 1e-9);
    // vertices.py import
    const Eigen::Vector3d centroid = v[2] + (v[4] - v[2]) / 2;
    const Eigen::Vector3d d((v[0] - v[3]).norm(), (v[0] - v[1]).norm(), (v[0] - v[4]).norm());
    // math3d.vertices2rotations, degrees
    Eigen::Vector3d r_deg = Eigen::Vector3d::Zero();
    const Eigen::Vector3d length = v[3] - v[0], width = v[1] - v[0];
    r_deg.z() = std::atan2(length.y(), length.x()) * 180 / M_PI;
    if (v[3].z() != v[0].z()) {
      const Eigen::Vector3d l = about(kZ, -radians(r_deg.z())) * length;
      r_deg.y() = -std::atan2(l.z(), l.x()) * 180 / M_PI;
    }
    if (v[0].z() != v[1].z()) {
      const Eigen::Vector3d w = about(kY, -radians(r_deg.y())) * about(kZ, -radians(r_deg.z())) * width;
      r_deg.x() = std::atan2(w.z(), w.y()) * 180 / M_PI;
    }
    CHECK((centroid - boxes[i].T_world_box.translation()).norm() < 1e-9);
    CHECK((d - boxes[i].size).norm() < 1e-9);
    // The same box: each corner labelCloud makes is one of OLT's. (Not always the same one: the
    // import skips an angle when two z's are exactly equal, so the box turned 180 degrees about x
    // comes back unturned, the same cuboid with top and bottom swapped.)
    for (int k = 0; k < 8; ++k) {
      double nearest = 1e300;
      for (const auto& c : box_corners(boxes[i]))
        nearest = std::min(nearest, (labelcloud_vertex(centroid, d, r_deg, k) - c).norm());
      CHECK(nearest < 1e-9);
    }
  }
}
