#include "olt/formats/annotations.h"

#include <cmath>
#include <set>

#include "olt/config/document.h"
#include "olt/config/schema.h"

namespace olt {

using nlohmann::json;

namespace {

// yaw_pitch_roll_deg written in radians: every value within 2 pi and one at least neither zero nor a
// multiple of 0.1 degree (what a person types for degrees) — 30 degrees written as 0.5236.
void check_degrees(const Document& doc, const json& list, std::vector<Diagnostic>& warnings) {
  std::string first_odd;
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].contains("yaw_pitch_roll_deg")) continue;
    for (size_t k = 0; k < 3; ++k) {
      const double v = list[i]["yaw_pitch_roll_deg"][k].get<double>();
      if (std::abs(v) > 2 * M_PI) return;
      const double tenths = v * 10;
      if (std::abs(tenths - std::round(tenths)) > 1e-6 && first_odd.empty())
        first_odd = "/boxes/" + std::to_string(i) + "/yaw_pitch_roll_deg/" + std::to_string(k);
    }
  }
  if (!first_odd.empty())
    warnings.push_back(doc.error_at(first_odd,
                                    "every yaw_pitch_roll_deg value is within 2 pi and this one is no "
                                    "round number of degrees: are they radians? The field is degrees "
                                    "(radians x 57.2958); or give \"rotation\" as a quaternion"));
}

}  // namespace

std::vector<Box> parse_native_annotations(const std::string& file, const std::string& text,
                                          std::vector<Diagnostic>* warnings) {
  const Document doc = parse_json_document(file, text);
  std::vector<Diagnostic> errors = validate_against_schema(doc, "annotations.schema.json");
  if (!errors.empty()) throw InputError(errors);

  std::vector<Box> boxes;
  std::set<std::string> ids;
  const json& list = doc.value.at("boxes");
  if (warnings) check_degrees(doc, list, *warnings);
  for (size_t i = 0; i < list.size(); ++i) {
    const json& b = list[i];
    const std::string at = "/boxes/" + std::to_string(i);
    Box box;
    box.id = b.at("id");
    const std::string name = "box '" + box.id + "' (boxes[" + std::to_string(i) + "])";
    if (!ids.insert(box.id).second)
      errors.push_back(doc.error_at(at + "/id", name + ": duplicate id '" + box.id + "'"));
    box.label = b.at("label");
    box.instance = b.value("instance", box.id);
    box.size = Eigen::Vector3d(b["size"][0], b["size"][1], b["size"][2]);
    for (int k = 0; k < 3; ++k)
      if (!(box.size[k] > 0))
        errors.push_back(
            doc.error_at(at + "/size/" + std::to_string(k),
                         name + ": size[" + std::to_string(k) + "] must be > 0, got " + b["size"][k].dump()));
    box.priority = b.value("priority", 0);
    box.margin_m = b.value("margin", 0.0);
    // Without a margin (0), a box of no height is the size's error alone.
    if (b.contains("margin") && !(box.margin_m >= 0 && box.margin_m < box.size.z()))
      errors.push_back(doc.error_at(at + "/margin", name + ": margin must be >= 0 and below the box's height (" +
                                                        json(box.size.z()).dump() + " m), got " +
                                                        json(box.margin_m).dump()));
    const Eigen::Vector3d center(b["center"][0], b["center"][1], b["center"][2]);
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    if (b.contains("rotation")) {
      const json& r = b["rotation"];
      q = Eigen::Quaterniond(r[3].get<double>(), r[0].get<double>(), r[1].get<double>(), r[2].get<double>());
      if (std::abs(q.norm() - 1.0) > kQuaternionNormTolerance)
        errors.push_back(doc.error_at(
            at + "/rotation",
            name + ": rotation must be a unit quaternion [qx, qy, qz, qw], norm is " + std::to_string(q.norm())));
    } else {
      const json& e = b["yaw_pitch_roll_deg"];
      q = Eigen::Quaterniond(rotation_from_ypr_deg(e[0], e[1], e[2]));
    }
    box.T_world_box = pose_from_tq(center, q);
    boxes.push_back(box);
  }
  if (!errors.empty()) throw InputError(errors);
  return boxes;
}

std::string format_native_annotations(const std::vector<Box>& boxes) {
  json list = json::array();
  for (const auto& b : boxes) {
    const json pose = pose_to_json(b.T_world_box);
    json j = {{"id", b.id},
              {"label", b.label},
              {"instance", b.instance},
              {"center", {pose[0], pose[1], pose[2]}},
              {"size", {b.size.x(), b.size.y(), b.size.z()}},
              {"rotation", {pose[3], pose[4], pose[5], pose[6]}}};
    if (b.priority != 0) j["priority"] = b.priority;
    if (b.margin_m != 0) j["margin"] = b.margin_m;
    list.push_back(j);
  }
  return json{{"version", 1}, {"boxes", list}}.dump(1) + "\n";
}

std::vector<Box> read_native_annotations(const std::string& text) {
  std::vector<Box> boxes;
  const json document = json::parse(text);  // named: a range over a temporary's member would dangle
  for (const json& b : document.at("boxes")) {
    Box box;
    box.id = b.at("id");
    box.label = b.at("label");
    box.instance = b.at("instance");
    box.size = Eigen::Vector3d(b.at("size")[0], b.at("size")[1], b.at("size")[2]);
    box.priority = b.value("priority", 0);
    box.margin_m = b.value("margin", 0.0);
    const json& c = b.at("center");
    const json& r = b.at("rotation");
    box.T_world_box = pose_from_tq(
        Eigen::Vector3d(c[0], c[1], c[2]),
        Eigen::Quaterniond(r[3].get<double>(), r[0].get<double>(), r[1].get<double>(), r[2].get<double>()));
    boxes.push_back(box);
  }
  return boxes;
}

}  // namespace olt
