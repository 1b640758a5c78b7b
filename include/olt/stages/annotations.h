#pragma once
// The `annotations` stage: the boxes of an annotation file (OLT's own format or a tool's), class
// names mapped and ignored classes dropped, moved from the frame they were drawn in (the levelled
// annotation frame, or the poses' frame) into the poses' frame; or the recording's own boxes
// (synthetic).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/geometry.h"
#include "olt/formats/box_formats.h"

namespace olt {

struct AnnotationsConfig {
  std::string format = "native";                 ///< one of box_formats(): native | labelcloud | ...
  std::string file;                              ///< annotation file; default: the recording's own boxes
  std::map<std::string, std::string> label_map;  ///< tool class -> OLT class
  std::vector<std::string> ignore;               ///< tool classes whose boxes are dropped
  /// The frame the file's boxes are in: "annotation" (the reconstruct stage's levelled frame, see
  /// olt/reconstruct/level.h), "world" (the poses' frame), or "auto": annotation where a file is
  /// given and a reconstruct stage is upstream, world otherwise.
  std::string frame = "auto";
};

struct AnnotationsInputs {
  std::string stage;            ///< the stage's id, for messages
  std::string recording_boxes;  ///< the recording's own boxes file, "" when it has none
  /// Where the file's boxes are drawn in the annotation frame: that frame in the poses' frame.
  std::optional<Pose> T_world_annotation;
};

/// The boxes, and the file's warnings (angles that look like the other unit); throws InputError
/// naming the file (and line) of a bad annotation, or when there is no file.
BoxFile run_annotations(const AnnotationsInputs& in, const AnnotationsConfig& c);

}  // namespace olt
