#pragma once
// One reader and writer per annotation tool (private to formats/; see box_formats.h).
#include <string>
#include <vector>

#include "olt/core/box.h"

namespace olt {

std::vector<Box> read_labelcloud(const std::string& file, const std::string& text, bool radians);
std::string write_labelcloud(const std::vector<Box>& boxes, bool radians);
std::vector<Box> read_sustechpoints(const std::string& file, const std::string& text);
std::string write_sustechpoints(const std::vector<Box>& boxes);
std::vector<Box> read_supervisely(const std::string& file, const std::string& text);
std::string write_supervisely(const std::vector<Box>& boxes);

/// A box from centre, full size and rotation; errors for non-positive sizes go to `reader`.
class FieldReader;
Box make_checked_box(FieldReader& reader, const std::string& pointer, const std::string& id, const std::string& label,
                     const std::string& instance, const Eigen::Vector3d& center, const Eigen::Vector3d& size,
                     const Eigen::Matrix3d& rotation);

}  // namespace olt
