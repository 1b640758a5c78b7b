// `annotations`: reads box annotations made elsewhere and normalises them (native format, rotation
// as a unit quaternion). Without `file`, the recording's own boxes are used (synthetic).
#include "olt/core/error.h"
#include "olt/formats/annotations.h"
#include "olt/formats/box_formats.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"

namespace olt {
namespace {

struct AnnotationsConfig {
  std::string format = "native";                 ///< native | labelcloud | sustechpoints | supervisely
  std::string file;                              ///< annotation file; default: the recording's own boxes
  std::map<std::string, std::string> label_map;  ///< tool class -> OLT class
  std::vector<std::string> ignore;               ///< tool classes whose boxes are dropped
};

std::shared_ptr<const Params<AnnotationsConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<AnnotationsConfig>>();
    t->choice("format", &AnnotationsConfig::format, box_formats(), "annotation file format")
        .path("file", &AnnotationsConfig::file, true, "annotation file; default: the recording's own boxes")
        .string_map("label_map", &AnnotationsConfig::label_map, "tool class -> OLT class")
        .strings("ignore", &AnnotationsConfig::ignore, "tool classes whose boxes are dropped");
    return t;
  }();
  return p;
}

std::vector<fs::path> files_read(const StageDecl& stage) {
  const AnnotationsConfig c = params()->from_json(stage.params);
  if (c.file.empty()) return {};
  read_boxes(c.format, c.file, read_file(c.file));  // bad input is found before anything runs
  return {c.file};
}

nlohmann::json run(const StageContext& ctx, ArtifactWriter& out) {
  const AnnotationsConfig c = params()->from_json(ctx.stage.params);
  std::string file = c.file;
  if (file.empty()) {
    const StageInput* source = ctx.input("source");
    if (source) file = load_recording(*source).boxes;
    if (file.empty())
      throw InputError("stage '" + ctx.stage.id + "'", "no annotation file given and the recording has no boxes");
  }
  const std::string format = c.file.empty() ? "native" : c.format;
  const std::vector<Box> boxes = map_labels(read_boxes(format, file, read_file(file)), c.label_map, c.ignore);
  out.write("boxes.json", format_native_annotations(boxes));
  out.publish("boxes.json", ctx.stage.id + "/boxes.json", "annotations");
  return {{"boxes", boxes.size()}};
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>& upstream, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const AnnotationsConfig c = params()->from_json(stage.params);
  if (!c.file.empty()) return;
  auto source = upstream.find("source");
  if (source == upstream.end() || source->second->params.value("format", "") != "synthetic")
    errors.push_back(doc.error_at(stage.pointer + "/params", "stage '" + stage.id +
                                                                 "' (annotations): give 'file'; only a synthetic "
                                                                 "recording carries its own boxes"));
}

}  // namespace

StageKind annotations_kind() {
  StageKind kind = make_stage_kind({"annotations", params(), {}, {"source"}, check}, 1, files_read, run);
  kind.light = true;  // parsing a box file: `olt plan` runs it aside to plan the labels in detail
  return kind;
}

}  // namespace olt
