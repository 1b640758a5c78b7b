// `annotations`: reads box annotations made elsewhere and normalises them (native format, rotation
// as a unit quaternion). Without `file`, the recording's own boxes are used (synthetic).
#include <spdlog/spdlog.h>

#include "olt/core/error.h"
#include "olt/formats/annotations.h"
#include "olt/formats/box_formats.h"
#include "olt/reconstruct/level.h"
#include "olt/stages/annotations.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
#include "olt/stages/typed_stage.h"

namespace olt {
namespace {

std::shared_ptr<const Params<AnnotationsConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<AnnotationsConfig>>();
    t->choice("format", &AnnotationsConfig::format, box_formats(), "annotation file format")
        .path("file", &AnnotationsConfig::file, true, "annotation file; default: the recording's own boxes")
        .string_map("label_map", &AnnotationsConfig::label_map, "tool class -> OLT class")
        .strings("ignore", &AnnotationsConfig::ignore, "tool classes whose boxes are dropped")
        .choice("frame", &AnnotationsConfig::frame, {"auto", "annotation", "world"},
                "frame of the file's boxes: the reconstruct stage's levelled annotation frame, or the poses' "
                "(world) frame; auto: annotation where a reconstruct stage is upstream");
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

}  // namespace

BoxFile run_annotations(const AnnotationsInputs& in, const AnnotationsConfig& c) {
  const std::string file = c.file.empty() ? in.recording_boxes : c.file;
  if (file.empty())
    throw InputError("stage '" + in.stage + "'", "no annotation file given and the recording has no boxes");
  const std::string format = c.file.empty() ? "native" : c.format;
  BoxFile read = read_box_file(format, file, read_file(file));
  read.boxes = map_labels(std::move(read.boxes), c.label_map, c.ignore);
  if (in.T_world_annotation)
    for (auto& b : read.boxes) b.T_world_box = *in.T_world_annotation * b.T_world_box;
  return read;
}

namespace {

AnnotationsInputs load(const StageContext& context) {
  // The recording (possibly large) is read only when its own boxes are used.
  const AnnotationsConfig c = params()->from_json(context.stage.params);
  const StageInput* source = context.input("source");
  const bool own = source && c.file.empty();
  AnnotationsInputs in{context.stage.id, own ? shared_recording(*source)->boxes : "", std::nullopt};
  const StageInput* scene = context.input("reconstruct");
  if (scene && !c.file.empty() && c.frame != "world")
    in.T_world_annotation =
        annotation_frame_from_json(nlohmann::json::parse(read_file(scene->artifact.path("annotation_frame.json"))))
            .T_world_annotation;
  return in;
}

// The warnings go to the log and into the summary, which a cached run shows again.
nlohmann::json save(const BoxFile& read, const StageContext& context, ArtifactWriter& out) {
  out.write("boxes.json", format_native_annotations(read.boxes));
  out.publish("boxes.json", context.stage.id + "/boxes.json", "annotations");
  nlohmann::json summary = {{"boxes", read.boxes.size()}};
  for (const auto& w : read.warnings) {
    spdlog::warn("{}: {}", context.stage.id, w.str());
    summary["warnings"].push_back(w.str());
  }
  return summary;
}

// The id of a reconstruct stage of the job that levels its scene (the default), "" where none does.
std::string levelled_scene_stage(const Document& doc) {
  if (!doc.value.is_object() || !doc.value.contains("stages") || !doc.value["stages"].is_object()) return "";
  for (const auto& [id, body] : doc.value["stages"].items()) {
    if (!body.is_object() || body.value("kind", nlohmann::json()) != "reconstruct") continue;
    const nlohmann::json params = body.value("params", nlohmann::json::object());
    if (!params.is_object() || params.value("level", nlohmann::json(true)) != false) return id;
  }
  return "";
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>& upstream, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const AnnotationsConfig c = params()->from_json(stage.params);
  if (c.frame == "annotation" && (c.file.empty() || !upstream.count("reconstruct")))
    errors.push_back(doc.error_at(stage.pointer + "/params/frame",
                                  "stage '" + stage.id + "' (annotations): frame: annotation " +
                                      (c.file.empty() ? "is for a file's boxes (the recording's own are in the "
                                                        "world frame)"
                                                      : "needs a reconstruct stage upstream (e.g. needs: [scene]), "
                                                        "whose levelled frame the boxes were drawn in")));
  // The published scene is levelled: a box file drawn on it is in the annotation frame, one from
  // elsewhere in the poses' frame. Which, only the user knows: where it could be either, say so.
  const std::string levelled = levelled_scene_stage(doc);
  if (!c.file.empty() && c.frame == "auto" && !upstream.count("reconstruct") && !levelled.empty())
    errors.push_back(
        doc.error_at(stage.pointer + "/params/file",
                     "stage '" + stage.id + "' (annotations): the job publishes a levelled scene (stage '" + levelled +
                         "'); say which frame the boxes of " + c.file + " are in: frame: annotation (drawn on " +
                         levelled + "/scene.ply; add needs: [" + levelled + "]) or frame: world (the poses' frame)"));
  if (!c.file.empty()) return;
  auto source = upstream.find("source");
  if (source == upstream.end() || source->second->params.value("format", "") != "synthetic")
    errors.push_back(doc.error_at(stage.pointer + "/params", "stage '" + stage.id +
                                                                 "' (annotations): give 'file'; only a synthetic "
                                                                 "recording carries its own boxes"));
}

}  // namespace

StageKind annotations_kind() {
  StageKind kind = make_stage_kind({"annotations", params(), {}, {"source", "reconstruct"}, check}, 3, files_read,
                                   typed_stage(params(), load, run_annotations, save));
  kind.light = true;  // parsing a box file: `olt plan` runs it aside to plan the labels in detail
  return kind;
}

}  // namespace olt
