// labelCloud (labelCloud/io/labels/centroid.py), "centroid_abs" label format: one JSON file per
// point cloud,
//   {"folder": "...", "filename": "...", "path": "...", "objects": [{"name": "cup",
//    "centroid": {"x", "y", "z"}, "dimensions": {"length", "width", "height"},
//    "rotations": {"x", "y", "z"}}]}
// centroid = box centre; length, width, height = full size along the box's x, y, z; rotations in
// degrees about the fixed x, y, z axes, R = Rz·Ry·Rx (utils/math3d.py rotate_around_zyx). The
// "centroid_rel" format is the same with radians in (-pi, pi]. labelCloud has no instance ids: each
// box is its own instance, named "<class>_<index>".
#include "json_fields.h"
#include "tool_formats.h"

namespace olt {

std::vector<Box> read_labelcloud(const std::string& file, const std::string& text, bool radians) {
  const double unit = radians ? 1.0 : M_PI / 180.0;
  const Document doc = parse_json_document(file, text);
  FieldReader reader(doc);
  std::vector<Box> boxes;
  const nlohmann::json& objects = reader.at("/objects", "objects");
  if (!objects.is_null() && !objects.is_array()) reader.error("/objects", "objects: expected a list");
  if (objects.is_array()) {
    for (size_t i = 0; i < objects.size(); ++i) {
      const std::string at = "/objects/" + std::to_string(i);
      const std::string label = reader.text(at + "/name", "objects[" + std::to_string(i) + "].name");
      const std::string id = label + "_" + std::to_string(i);
      const Eigen::Vector3d center = reader.vector(at + "/centroid", "centroid");
      const Eigen::Vector3d size = reader.vector(at + "/dimensions", "dimensions", {"length", "width", "height"});
      const Eigen::Vector3d angles = reader.vector(at + "/rotations", "rotations") * unit;
      boxes.push_back(make_checked_box(reader, at, id, label, "", center, size, rotation_zyx(angles)));
    }
  }
  reader.throw_if_errors();
  return boxes;
}

std::string write_labelcloud(const std::vector<Box>& boxes, bool radians) {
  const double unit = radians ? 1.0 : M_PI / 180.0;
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& b : boxes) {
    const Eigen::Vector3d c = b.T_world_box.translation();
    const Eigen::Vector3d r = angles_zyx(b.T_world_box.linear()) / unit;
    objects.push_back({{"name", b.label},
                       {"centroid", xyz_json(c)},
                       {"dimensions", {{"length", b.size.x()}, {"width", b.size.y()}, {"height", b.size.z()}}},
                       {"rotations", xyz_json(r)}});
  }
  return nlohmann::json{{"folder", "pointclouds"},
                        {"filename", "scene.pcd"},
                        {"path", "pointclouds/scene.pcd"},
                        {"objects", objects}}
             .dump(2) +
         "\n";
}

}  // namespace olt
