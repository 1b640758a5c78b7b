#pragma once
// The `annotations` stage: the boxes of an annotation file (OLT's own format or a tool's), class
// names mapped and ignored classes dropped; or the recording's own boxes (synthetic).
#include <map>
#include <string>
#include <vector>

#include "olt/core/box.h"
#include "olt/formats/box_formats.h"

namespace olt {

struct AnnotationsConfig {
  std::string format = "native";                 ///< one of box_formats(): native | labelcloud | ...
  std::string file;                              ///< annotation file; default: the recording's own boxes
  std::map<std::string, std::string> label_map;  ///< tool class -> OLT class
  std::vector<std::string> ignore;               ///< tool classes whose boxes are dropped
};

struct AnnotationsInputs {
  std::string stage;            ///< the stage's id, for messages
  std::string recording_boxes;  ///< the recording's own boxes file, "" when it has none
};

/// The boxes, and the file's warnings (angles that look like the other unit); throws InputError
/// naming the file (and line) of a bad annotation, or when there is no file.
BoxFile run_annotations(const AnnotationsInputs& in, const AnnotationsConfig& c);

}  // namespace olt
