// Supervisely point-cloud annotation (`ann/<cloud>.pcd.json`; CVAT exports the same):
//   {"description": "", "key": "...", "tags": [], "objects": [{"key": "k1", "classTitle": "car",
//    "tags": []}], "figures": [{"key": "f1", "objectKey": "k1", "geometryType": "cuboid_3d",
//    "geometry": {"position": {"x", "y", "z"}, "rotation": {"x", "y", "z"},
//    "dimensions": {"x", "y", "z"}}}]}
// position = box centre; dimensions = full size along the box's x, y, z; rotation in radians,
// R = Rx·Ry·Rz. Figures of other geometry types are skipped. An object (its key) is an instance;
// several figures may share it.
#include <map>

#include "json_fields.h"
#include "tool_formats.h"

namespace olt {

std::vector<Box> read_supervisely(const std::string& file, const std::string& text) {
  const Document doc = parse_json_document(file, text);
  FieldReader reader(doc);
  std::map<std::string, std::string> class_of;
  const nlohmann::json& objects = reader.at("/objects", "objects");
  for (size_t i = 0; objects.is_array() && i < objects.size(); ++i) {
    const std::string at = "/objects/" + std::to_string(i);
    class_of[reader.text(at + "/key", "objects[" + std::to_string(i) + "].key")] =
        reader.text(at + "/classTitle", "objects[" + std::to_string(i) + "].classTitle");
  }
  std::vector<Box> boxes;
  std::map<std::string, size_t> figure_of;  // a box's id: the figure that has it
  const nlohmann::json& figures = reader.at("/figures", "figures");
  for (size_t i = 0; figures.is_array() && i < figures.size(); ++i) {
    const std::string at = "/figures/" + std::to_string(i);
    const std::string name = "figures[" + std::to_string(i) + "]";
    if (!figures[i].is_object() || figures[i].value("geometryType", "") != "cuboid_3d") continue;
    const std::string object = reader.text(at + "/objectKey", name + ".objectKey");
    auto it = class_of.find(object);
    if (it == class_of.end()) {
      reader.error(at + "/objectKey", name + ".objectKey: no object with key '" + object + "'");
      continue;
    }
    const std::string id = figures[i].contains("key") ? reader.text(at + "/key", name + ".key") : name;
    if (const auto [first, fresh] = figure_of.emplace(id, i); !fresh)
      reader.error(at + (figures[i].contains("key") ? "/key" : ""), name + ": id '" + id + "' is also figures[" +
                                                                        std::to_string(first->second) +
                                                                        "]'s: every figure needs a key of its own");
    const Eigen::Vector3d center = reader.vector(at + "/geometry/position", name + ".geometry.position");
    const Eigen::Vector3d size = reader.vector(at + "/geometry/dimensions", name + ".geometry.dimensions");
    const Eigen::Vector3d angles = reader.vector(at + "/geometry/rotation", name + ".geometry.rotation");
    boxes.push_back(make_checked_box(reader, at, id, it->second, object, center, size, rotation_xyz(angles)));
  }
  reader.throw_if_errors();
  return boxes;
}

std::string write_supervisely(const std::vector<Box>& boxes) {
  nlohmann::json objects = nlohmann::json::array(), figures = nlohmann::json::array();
  std::map<std::string, std::string> written;
  for (const auto& b : boxes) {
    if (written.emplace(b.instance, b.label).second)
      objects.push_back({{"key", b.instance}, {"classTitle", b.label}, {"tags", nlohmann::json::array()}});
    const Eigen::Vector3d c = b.T_world_box.translation();
    const Eigen::Vector3d r = angles_xyz(b.T_world_box.linear());
    figures.push_back(
        {{"key", b.id},
         {"objectKey", b.instance},
         {"geometryType", "cuboid_3d"},
         {"geometry", {{"position", xyz_json(c)}, {"rotation", xyz_json(r)}, {"dimensions", xyz_json(b.size)}}}});
  }
  return nlohmann::json{{"description", ""},
                        {"key", "olt"},
                        {"tags", nlohmann::json::array()},
                        {"objects", objects},
                        {"figures", figures}}
             .dump(2) +
         "\n";
}

}  // namespace olt
