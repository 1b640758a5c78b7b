// SUSTechPOINTS, one label file per frame (data/<scene>/label/<frame>.json): a bare JSON array, or
// in the newer server's files {"objs": [...]}, of
//   {"obj_type": "Car", "obj_id": "3", "obj_attr": "", "psr": {"position": {"x", "y", "z"},
//    "scale": {"x", "y", "z"}, "rotation": {"x", "y", "z"}}}
// position = box centre; scale = full size along the box's x, y, z; rotation in radians, applied
// as a three.js Euler with its default order "XYZ" (intrinsic): R = Rx·Ry·Rz (doc/data-format.md,
// src/editor/js/annotation.js createCuboid). obj_id is a string, "" = none; obj_attr is free text,
// comma-separated attribute words (src/editor/js/common/attr_editor.js).
//
// Both layouts are read; the bare array is written, the one every version of the web app loads. The
// tool's label checker (tools/check_labels.py) refuses an obj_id seen twice in a frame, so OLT
// writes one obj_id per box: the instance name for its first box (ids made in SUSTechPOINTS come
// back unchanged), "<instance>-2", "-3", ... for its further boxes, skipping ids already taken; a
// box whose obj_id is not its instance's name carries the instance as the attribute
// "olt_instance=<name>" in obj_attr. Reading, the instance is that attribute, else obj_id (boxes of
// one obj_id are one instance, as SUSTechPOINTS tracks an object by its id), else the box alone.
#include <map>
#include <set>

#include "json_fields.h"
#include "olt/core/error.h"
#include "tool_formats.h"

namespace olt {
namespace {

const std::string kInstanceAttribute = "olt_instance=";

std::string trimmed(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t"), end = s.find_last_not_of(" \t");
  return begin == std::string::npos ? "" : s.substr(begin, end - begin + 1);
}

// The value of "olt_instance=NAME" among the comma-separated attributes, "" when absent.
std::string instance_attribute(const nlohmann::json& object) {
  const auto attr = object.find("obj_attr");
  if (attr == object.end() || !attr->is_string()) return "";
  const std::string text = attr->get<std::string>();
  for (size_t begin = 0; begin <= text.size();) {
    const size_t end = std::min(text.find(',', begin), text.size());
    const std::string entry = trimmed(text.substr(begin, end - begin));
    if (entry.rfind(kInstanceAttribute, 0) == 0) return entry.substr(kInstanceAttribute.size());
    begin = end + 1;
  }
  return "";
}

std::string instance_name(const Box& b) { return !b.instance.empty() ? b.instance : !b.id.empty() ? b.id : "box"; }

// One obj_id per box, unique in the file (see the top of this file).
std::vector<std::string> unique_obj_ids(const std::vector<Box>& boxes) {
  std::set<std::string> taken;
  for (const auto& b : boxes) taken.insert(instance_name(b));
  std::set<std::string> named;  // instances whose first box has its name as obj_id
  std::map<std::string, int> next_suffix;
  std::vector<std::string> ids;
  for (const auto& b : boxes) {
    const std::string name = instance_name(b);
    if (named.insert(name).second) {
      ids.push_back(name);
      continue;
    }
    std::string id;
    do id = name + "-" + std::to_string(next_suffix.emplace(name, 2).first->second++);
    while (taken.count(id));
    taken.insert(id);
    ids.push_back(id);
  }
  return ids;
}

}  // namespace

std::vector<Box> read_sustechpoints(const std::string& file, const std::string& text) {
  const Document doc = parse_json_document(file, text);
  FieldReader reader(doc);
  std::vector<Box> boxes;
  const bool wrapped = doc.value.is_object() && doc.value.contains("objs");
  const nlohmann::json& list = wrapped ? doc.value["objs"] : doc.value;
  const std::string root = wrapped ? "/objs" : "";
  if (!list.is_array()) reader.error(root, "expected a JSON array of objects, or {\"objs\": [...]}");
  for (size_t i = 0; list.is_array() && i < list.size(); ++i) {
    const std::string at = root + "/" + std::to_string(i);
    const std::string label = reader.text(at + "/obj_type", "[" + std::to_string(i) + "].obj_type");
    const bool has_id = list[i].is_object() && list[i].contains("obj_id") && list[i]["obj_id"] != "";
    const std::string obj_id = has_id ? reader.text(at + "/obj_id", "obj_id") : "";
    const std::string id = has_id ? label + "_" + obj_id + "_" + std::to_string(i) : label + "_" + std::to_string(i);
    const std::string attribute = list[i].is_object() ? instance_attribute(list[i]) : "";
    const Eigen::Vector3d center = reader.vector(at + "/psr/position", "psr.position");
    const Eigen::Vector3d size = reader.vector(at + "/psr/scale", "psr.scale");
    const Eigen::Vector3d angles = reader.vector(at + "/psr/rotation", "psr.rotation");
    boxes.push_back(make_checked_box(reader, at, id, label, attribute.empty() ? obj_id : attribute, center, size,
                                     rotation_xyz(angles)));
  }
  reader.throw_if_errors();
  return boxes;
}

std::string write_sustechpoints(const std::vector<Box>& boxes) {
  const std::vector<std::string> ids = unique_obj_ids(boxes);
  nlohmann::json out = nlohmann::json::array();
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    const std::string name = instance_name(b);
    if (ids[i] != name && name.find(',') != std::string::npos)
      throw InputError("--to=sustechpoints", "box '" + b.id + "': instance '" + name +
                                                 "' holds a ',', which separates SUSTechPOINTS's attributes "
                                                 "(obj_attr, where its instance is kept); rename the instance");
    const Eigen::Vector3d c = b.T_world_box.translation();
    const Eigen::Vector3d r = angles_xyz(b.T_world_box.linear());
    out.push_back({{"obj_type", b.label},
                   {"obj_id", ids[i]},
                   {"obj_attr", ids[i] == name ? "" : kInstanceAttribute + name},
                   {"psr", {{"position", xyz_json(c)}, {"scale", xyz_json(b.size)}, {"rotation", xyz_json(r)}}}});
  }
  return out.dump(2) + "\n";
}

}  // namespace olt
