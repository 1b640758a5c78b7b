// SUSTechPOINTS, one label file per frame (data/<scene>/label/<frame>.json): {"objs": [...]}, or in
// older files the bare array, of
//   {"obj_type": "Car", "obj_id": "3", "obj_attr": "", "psr": {"position": {"x", "y", "z"},
//    "scale": {"x", "y", "z"}, "rotation": {"x", "y", "z"}}}
// position = box centre; scale = full size along the box's x, y, z; rotation in radians, applied
// as a three.js Euler with its default order "XYZ" (intrinsic): R = Rx·Ry·Rz (doc/data-format.md,
// src/editor/js/annotation.js createCuboid). obj_id names the instance ("" = none).
#include "json_fields.h"
#include "tool_formats.h"

namespace olt {

std::vector<Box> read_sustechpoints(const std::string& file, const std::string& text) {
  const Document doc = parse_json_document(file, text);
  FieldReader reader(doc);
  std::vector<Box> boxes;
  const bool wrapped = doc.value.is_object() && doc.value.contains("objs");
  const nlohmann::json& list = wrapped ? doc.value["objs"] : doc.value;
  const std::string root = wrapped ? "/objs" : "";
  if (!list.is_array()) reader.error(root, "expected {\"objs\": [...]} or a JSON array of objects");
  for (size_t i = 0; list.is_array() && i < list.size(); ++i) {
    const std::string at = root + "/" + std::to_string(i);
    const std::string label = reader.text(at + "/obj_type", "[" + std::to_string(i) + "].obj_type");
    const bool has_id = list[i].is_object() && list[i].contains("obj_id") && list[i]["obj_id"] != "";
    const std::string instance = has_id ? reader.text(at + "/obj_id", "obj_id") : "";
    const std::string id = has_id ? label + "_" + instance + "_" + std::to_string(i) : label + "_" + std::to_string(i);
    const Eigen::Vector3d center = reader.vector(at + "/psr/position", "psr.position");
    const Eigen::Vector3d size = reader.vector(at + "/psr/scale", "psr.scale");
    const Eigen::Vector3d angles = reader.vector(at + "/psr/rotation", "psr.rotation");
    boxes.push_back(make_checked_box(reader, at, id, label, instance, center, size, rotation_xyz(angles)));
  }
  reader.throw_if_errors();
  return boxes;
}

std::string write_sustechpoints(const std::vector<Box>& boxes) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& b : boxes) {
    const Eigen::Vector3d c = b.T_world_box.translation();
    const Eigen::Vector3d r = angles_xyz(b.T_world_box.linear());
    out.push_back({{"obj_type", b.label},
                   {"obj_id", b.instance},
                   {"obj_attr", ""},
                   {"psr", {{"position", xyz_json(c)}, {"scale", xyz_json(b.size)}, {"rotation", xyz_json(r)}}}});
  }
  return nlohmann::json{{"objs", out}}.dump(2) + "\n";
}

}  // namespace olt
