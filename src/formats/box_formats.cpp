#include "olt/formats/box_formats.h"

#include <algorithm>
#include <map>

#include "json_fields.h"
#include "olt/core/error.h"
#include "olt/formats/annotations.h"
#include "tool_formats.h"

namespace olt {

const std::vector<std::string>& box_formats() {
  static const std::vector<std::string> formats = {
      "native", "labelcloud", "labelcloud_rel", "labelcloud_vertices", "sustechpoints", "supervisely"};
  return formats;
}

namespace {

BoxFile parse_boxes(const std::string& format, const std::string& file, const std::string& text) {
  if (format == "native") {
    BoxFile read;
    read.boxes = parse_native_annotations(file, text, &read.warnings);
    return read;
  }
  if (format == "labelcloud") return read_labelcloud(file, text, false);
  if (format == "labelcloud_rel") return read_labelcloud(file, text, true);
  if (format == "labelcloud_vertices") return read_labelcloud_vertices(file, text);
  if (format == "sustechpoints") return {read_sustechpoints(file, text), {}};
  if (format == "supervisely") return {read_supervisely(file, text), {}};
  throw InputError(file, "unknown box format '" + format + "'");
}

}  // namespace

BoxFile read_box_file(const std::string& format, const std::string& file, const std::string& text) {
  BoxFile read = parse_boxes(format, file, text);
  // Every frame tests its boxes in view: a file of this many is a mistake (a point cloud exported
  // as boxes, a generator gone wrong), and labeling with it would take hours.
  if (read.boxes.size() > kMaxBoxes)
    throw InputError(file, std::to_string(read.boxes.size()) + " boxes; at most " + std::to_string(kMaxBoxes) +
                               " are read from one file");
  // A box is named by its id in every frame's record and file (the native reader says where first).
  std::map<std::string, size_t> first;
  for (size_t i = 0; i < read.boxes.size(); ++i)
    if (const auto [at, fresh] = first.emplace(read.boxes[i].id, i); !fresh)
      throw InputError(file, "boxes " + std::to_string(at->second) + " and " + std::to_string(i) +
                                 " have the same id '" + read.boxes[i].id + "': every box needs an id of its own");
  return read;
}

std::vector<Box> read_boxes(const std::string& format, const std::string& file, const std::string& text) {
  return read_box_file(format, file, text).boxes;
}

std::string write_boxes(const std::string& format, const std::vector<Box>& boxes) {
  if (format == "native") return format_native_annotations(boxes);
  if (format == "labelcloud") return write_labelcloud(boxes, false);
  if (format == "labelcloud_rel") return write_labelcloud(boxes, true);
  if (format == "labelcloud_vertices") return write_labelcloud_vertices(boxes);
  if (format == "sustechpoints") return write_sustechpoints(boxes);
  if (format == "supervisely") return write_supervisely(boxes);
  throw InputError("--to", "unknown box format '" + format + "'");
}

std::vector<Box> map_labels(std::vector<Box> boxes, const std::map<std::string, std::string>& label_map,
                            const std::vector<std::string>& ignore) {
  boxes.erase(std::remove_if(boxes.begin(), boxes.end(),
                             [&](const Box& b) { return std::count(ignore.begin(), ignore.end(), b.label) > 0; }),
              boxes.end());
  for (auto& b : boxes)
    if (auto it = label_map.find(b.label); it != label_map.end()) b.label = it->second;
  return boxes;
}

Box make_checked_box(FieldReader& reader, const std::string& pointer, const std::string& id, const std::string& label,
                     const std::string& instance, const Eigen::Vector3d& center, const Eigen::Vector3d& size,
                     const Eigen::Matrix3d& rotation) {
  for (int k = 0; k < 3; ++k)
    if (!(size[k] > 0))
      reader.error(pointer, "box '" + id + "': size along " + std::string(1, "xyz"[k]) + " must be > 0, got " +
                                std::to_string(size[k]));
  Box box;
  box.id = id;
  box.label = label;
  box.instance = instance.empty() ? id : instance;
  box.size = size;
  box.T_world_box = pose_from_tq(center, Eigen::Quaterniond(rotation));
  return box;
}

}  // namespace olt
