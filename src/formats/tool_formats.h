#pragma once
// One reader and writer per annotation tool (private to formats/; see box_formats.h).
#include <string>
#include <utility>
#include <vector>

#include "olt/core/box.h"
#include "olt/formats/box_formats.h"

namespace olt {

class FieldReader;

BoxFile read_labelcloud(const std::string& file, const std::string& text, bool radians);
std::string write_labelcloud(const std::vector<Box>& boxes, bool radians);
BoxFile read_labelcloud_vertices(const std::string& file, const std::string& text);
std::string write_labelcloud_vertices(const std::vector<Box>& boxes);
std::vector<Box> read_sustechpoints(const std::string& file, const std::string& text);
std::string write_sustechpoints(const std::vector<Box>& boxes);
std::vector<Box> read_supervisely(const std::string& file, const std::string& text);
std::string write_supervisely(const std::vector<Box>& boxes);

/// A box from centre, full size and rotation; errors for non-positive sizes go to `reader`.
Box make_checked_box(FieldReader& reader, const std::string& pointer, const std::string& id, const std::string& label,
                     const std::string& instance, const Eigen::Vector3d& center, const Eigen::Vector3d& size,
                     const Eigen::Matrix3d& rotation);

// labelCloud's two layouts share a file (labelcloud_common.cpp).

/// The file's "objects" list (null when absent, after an error). A file in labelCloud's other
/// layout (no object holds `key`, "centroid" or "vertices", but one holds the other) is refused
/// with one error naming the format to use, instead of one "missing" per field.
const nlohmann::json& labelcloud_objects(FieldReader& reader, const std::string& key);
/// {"folder", "filename", "path", "objects"}, as labelCloud writes them.
std::string labelcloud_file_text(const nlohmann::ordered_json& objects);
/// The rotations of a centroid file, each with the JSON pointer of its object: an error where they
/// cannot be in the format's unit (radians beyond 2 pi), a warning where they look like the other.
void check_labelcloud_angle_units(FieldReader& reader,
                                  const std::vector<std::pair<std::string, Eigen::Vector3d>>& rotations, bool radians);

}  // namespace olt
