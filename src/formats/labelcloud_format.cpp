// labelCloud (labelCloud/io/labels/centroid.py), "centroid_abs" label format: one JSON file per
// point cloud,
//   {"folder": "...", "filename": "...", "path": "...", "objects": [{"name": "cup",
//    "centroid": {"x", "y", "z"}, "dimensions": {"length", "width", "height"},
//    "rotations": {"x", "y", "z"}}]}
// centroid = box centre; length, width, height = full size along the box's x, y, z; rotations in
// degrees about the fixed x, y, z axes, R = Rz·Ry·Rx (utils/math3d.py rotate_around_zyx),
// normalised to [0, 360) (model/bbox.py set_rotations). The "centroid_rel" format is the same with
// radians in (-pi, pi]. labelCloud's import reads the three members by order, not by key, so they
// are written in the order above. labelCloud has no instance ids: each box is its own instance,
// named "<class>_<index>".
#include <cmath>

#include "json_fields.h"
#include "tool_formats.h"

namespace olt {
namespace {

// The angle as labelCloud stores it: degrees in [0, 360), radians in (-pi, pi].
double labelcloud_angle(double radians_value, bool radians) {
  if (radians) return radians_value <= -M_PI ? radians_value + 2 * M_PI : radians_value;
  double degrees = std::fmod(radians_value * 180.0 / M_PI, 360.0);
  if (degrees < 0) degrees += 360.0;
  if (degrees >= 360.0) degrees = 0;  // a tiny negative angle, rounded up by the addition
  return degrees + 0.0;               // no -0
}

nlohmann::ordered_json xyz_in_order(const Eigen::Vector3d& v) {
  nlohmann::ordered_json out;
  out["x"] = v.x();
  out["y"] = v.y();
  out["z"] = v.z();
  return out;
}

}  // namespace

BoxFile read_labelcloud(const std::string& file, const std::string& text, bool radians) {
  const double unit = radians ? 1.0 : M_PI / 180.0;
  const Document doc = parse_json_document(file, text);
  FieldReader reader(doc);
  std::vector<Box> boxes;
  std::vector<std::pair<std::string, Eigen::Vector3d>> rotations;
  const nlohmann::json& objects = labelcloud_objects(reader, "centroid");
  for (size_t i = 0; objects.is_array() && i < objects.size(); ++i) {
    const std::string at = "/objects/" + std::to_string(i);
    const std::string label = reader.text(at + "/name", "objects[" + std::to_string(i) + "].name");
    const std::string id = label + "_" + std::to_string(i);
    const Eigen::Vector3d center = reader.vector(at + "/centroid", "centroid");
    const Eigen::Vector3d size = reader.vector(at + "/dimensions", "dimensions", {"length", "width", "height"});
    const Eigen::Vector3d angles = reader.vector(at + "/rotations", "rotations");
    rotations.emplace_back(at, angles);
    boxes.push_back(make_checked_box(reader, at, id, label, "", center, size, rotation_zyx(angles * unit)));
  }
  check_labelcloud_angle_units(reader, rotations, radians);
  reader.throw_if_errors();
  return {boxes, reader.warnings()};
}

std::string write_labelcloud(const std::vector<Box>& boxes, bool radians) {
  nlohmann::ordered_json objects = nlohmann::ordered_json::array();
  for (const auto& b : boxes) {
    Eigen::Vector3d r = angles_zyx(b.T_world_box.linear());
    for (int k = 0; k < 3; ++k) r[k] = labelcloud_angle(r[k], radians);
    nlohmann::ordered_json object, dimensions;
    dimensions["length"] = b.size.x();
    dimensions["width"] = b.size.y();
    dimensions["height"] = b.size.z();
    object["name"] = b.label;
    object["centroid"] = xyz_in_order(b.T_world_box.translation());
    object["dimensions"] = dimensions;
    object["rotations"] = xyz_in_order(r);
    objects.push_back(object);
  }
  return labelcloud_file_text(objects);
}

}  // namespace olt
