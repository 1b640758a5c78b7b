#pragma once
// Box annotation files of the point-cloud annotation tools people use, converted to and from the
// native model (olt/formats/annotations.h). Conventions (README, "Box formats"):
//   labelcloud     labelCloud "centroid_abs" JSON: centroid = centre; dimensions length/width/
//                  height = size along the box's x/y/z; rotations x/y/z in degrees, R = Rz·Ry·Rx
//   labelcloud_rel labelCloud "centroid_rel": the same with radians
//   labelcloud_vertices
//                  labelCloud "vertices": each box's 8 corners in labelCloud's order, the box
//                  fitted to all eight (a full rotation)
//   sustechpoints  SUSTechPOINTS per-frame JSON array: psr.position = centre, psr.scale = full
//                  size, psr.rotation x/y/z in radians, three.js Euler "XYZ": R = Rx·Ry·Rz;
//                  obj_type = class; obj_id unique per box, the instance in obj_attr
//                  "olt_instance=NAME" (else obj_id is the instance)
//   supervisely    Supervisely point-cloud annotation (also CVAT's export): figures of
//                  geometryType cuboid_3d, geometry.position = centre, dimensions = full size,
//                  rotation x/y/z in radians, R = Rx·Ry·Rz (CVAT's three.js cuboid; Supervisely
//                  documents only yaw-only boxes, where this is Rz); objects[].classTitle =
//                  class, objectKey = instance
#include <map>
#include <string>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/error.h"

namespace olt {

/// Every format name, native first.
const std::vector<std::string>& box_formats();

/// The boxes of one file, and what looks wrong in it without proving it wrong (angles that look like
/// the other unit): the caller shows the warnings, e.g. in a stage's summary.
struct BoxFile {
  std::vector<Box> boxes;
  std::vector<Diagnostic> warnings;  ///< FILE:LINE:COLUMN of the value in doubt, and the format to try
};

/// Parses `text` (the content of `file`) in `format`; throws InputError naming file, line and box.
BoxFile read_box_file(const std::string& format, const std::string& file, const std::string& text);
/// read_box_file's boxes alone, where the warnings are shown elsewhere (a job's validation: the
/// stage's run reports them).
std::vector<Box> read_boxes(const std::string& format, const std::string& file, const std::string& text);

/// The most boxes one annotation file may hold (read_boxes refuses more, naming the file).
inline constexpr size_t kMaxBoxes = 10000;

/// The file content of `boxes` in `format` (deterministic). Instances a tool cannot express are lost.
std::string write_boxes(const std::string& format, const std::vector<Box>& boxes);

/// Renames classes by `label_map` (tool class -> OLT class) and drops boxes whose class (before
/// renaming) is in `ignore`.
std::vector<Box> map_labels(std::vector<Box> boxes, const std::map<std::string, std::string>& label_map,
                            const std::vector<std::string>& ignore);

}  // namespace olt
