// What labelCloud's label formats share: the file around the objects, telling its centroid and
// vertices layouts apart, and the angle unit of the centroid formats ("centroid_abs": degrees in
// [0, 360); "centroid_rel": radians in (-pi, pi], labelCloud/io/labels/base.py abs2rel_rotation).
#include <cmath>

#include "json_fields.h"
#include "tool_formats.h"

namespace olt {
namespace {

std::string layout_name(const std::string& key) {
  return key == "vertices" ? "labelCloud's vertices format (format: labelcloud_vertices)"
                           : "labelCloud's centroid format (format: labelcloud for degrees, labelcloud_rel "
                             "for radians)";
}

bool any_holds(const nlohmann::json& objects, const std::string& key) {
  for (const auto& o : objects)
    if (o.is_object() && o.contains(key)) return true;
  return false;
}

// The angles of one kind found in a file: how many, and the first (name = value, and where).
struct Found {
  int count = 0;
  std::string first, pointer;

  void add(const std::string& name, const std::string& at) {
    if (count++ == 0) first = name, pointer = at;
  }
  std::string and_more() const { return count > 1 ? " (and " + std::to_string(count - 1) + " more)" : ""; }
};

bool whole(double v) { return std::abs(v - std::round(v)) < 1e-6; }
// A value a person would type for degrees: a multiple of 0.1 (radians are seldom one).
bool round_degrees(double v) { return whole(v * 10); }

}  // namespace

const nlohmann::json& labelcloud_objects(FieldReader& reader, const std::string& key) {
  const nlohmann::json& objects = reader.at("/objects", "objects");
  if (objects.is_null()) return objects;
  if (!objects.is_array()) {
    reader.error("/objects", "objects: expected a list");
    reader.throw_if_errors();
  }
  const std::string other = key == "vertices" ? "centroid" : "vertices";
  if (!any_holds(objects, key) && any_holds(objects, other)) {
    reader.error("/objects", "the objects hold '" + other + "', not '" + key + "': this file is in " +
                                 layout_name(other) + ", not in " + layout_name(key));
    reader.throw_if_errors();
  }
  return objects;
}

std::string labelcloud_file_text(const nlohmann::ordered_json& objects) {
  // Keys in labelCloud's order: its import reads centroid, dimensions and rotations by .values().
  nlohmann::ordered_json file;
  file["folder"] = "pointclouds";
  file["filename"] = "scene.pcd";
  file["path"] = "pointclouds/scene.pcd";
  file["objects"] = objects;
  return file.dump(2) + "\n";
}

void check_labelcloud_angle_units(FieldReader& reader,
                                  const std::vector<std::pair<std::string, Eigen::Vector3d>>& rotations, bool radians) {
  const double kTolerance = 1e-6;  // labelCloud rounds to export_precision decimals
  Found beyond_2pi, outside_pi, nonzero, not_whole, not_round_degrees;
  for (const auto& [pointer, angles] : rotations) {
    for (int k = 0; k < 3; ++k) {
      const double v = angles[k];
      const std::string axis(1, "xyz"[k]);
      const std::string name = "objects[" + pointer.substr(pointer.rfind('/') + 1) + "].rotations." + axis + " = " +
                               nlohmann::json(v).dump();
      const std::string at = pointer + "/rotations/" + axis;
      if (std::abs(v) > 2 * M_PI + kTolerance) beyond_2pi.add(name, at);
      if (std::abs(v) > M_PI + kTolerance) outside_pi.add(name, at);
      if (v == 0) continue;
      nonzero.add(name, at);
      if (!whole(v)) not_whole.add(name, at);
      if (!round_degrees(v)) not_round_degrees.add(name, at);
    }
  }
  const std::string use_degrees = "; if the angles are degrees (labelCloud's centroid_abs), use format: labelcloud";
  if (radians && beyond_2pi.count > 0)
    reader.error(beyond_2pi.pointer, beyond_2pi.first + beyond_2pi.and_more() +
                                         " is beyond 2 pi, so not radians (labelCloud's centroid_rel writes "
                                         "(-pi, pi])" +
                                         use_degrees);
  else if (radians && outside_pi.count > 0)
    reader.warn(outside_pi.pointer, outside_pi.first + outside_pi.and_more() +
                                        " is outside (-pi, pi], where labelCloud's centroid_rel puts every angle" +
                                        use_degrees);
  else if (radians && nonzero.count > 0 && not_whole.count == 0)
    reader.warn(nonzero.pointer, "every non-zero angle is a whole number, as radians seldom are" + use_degrees);
  else if (!radians && nonzero.count > 0 && beyond_2pi.count == 0 && not_round_degrees.count > 0)
    reader.warn(not_round_degrees.pointer,
                "every angle is within 2 pi and " + not_round_degrees.first +
                    " is not a round number of degrees: these look like radians; if they are (labelCloud's "
                    "centroid_rel), use format: labelcloud_rel");
}

}  // namespace olt
