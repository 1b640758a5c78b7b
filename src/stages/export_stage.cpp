// `export`: the propagated labels in the forms training code reads:
//   labels.yaml                      class ids, names, colours, and the values to ignore
//   instances.json                   COCO instance annotations (RLE masks, boxes) per labeled image
//   <sensor>/boxes/<observation>.json  each visible box in that observation's sensor frame
// Masks are at depth resolution, which equals the colour resolution for registered RGB-D data
// (TUM, synthetic); `image` entries name the colour image. The masks come run-length encoded from
// the labeled frames (masks.json), not from decoding their instance images again.
#include <algorithm>
#include <optional>

#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/parallel.h"
#include "olt/core/process_memory.h"
#include "olt/core/progress.h"
#include "olt/core/run_memory.h"
#include "olt/formats/coco.h"
#include "olt/propagate/label_map.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/export.h"
#include "olt/stages/kinds.h"
#include "olt/stages/typed_stage.h"

namespace olt {
namespace {

std::shared_ptr<const Params<ExportConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<ExportConfig>>();
    t->boolean("coco", &ExportConfig::coco, "write COCO instances.json")
        .boolean("sensor_boxes", &ExportConfig::sensor_boxes, "write per-observation boxes in the sensor frame");
    return t;
  }();
  return p;
}

std::string labels_yaml(const LabelMap& map) {
  std::string text =
      "# OLT label map. Class and instance images are 16-bit PNGs: 0 = unlabeled (a depth point in no\n"
      "# box), 65535 = no depth (ignore in training).\n"
      "unlabeled: 0\nignore_index: 65535\nclasses:\n";
  for (const auto& c : map.classes)
    text += "  - {id: " + std::to_string(c.id) + ", name: \"" + c.name + "\", color: [" + std::to_string(c.color[0]) +
            ", " + std::to_string(c.color[1]) + ", " + std::to_string(c.color[2]) + "]}\n";
  return text;
}

// A COCO entry as nlohmann's compact dump writes it (keys sorted), in two pieces around its ids, which
// are known only once every earlier frame's entries are counted: `head` ends with "\"id\":", `tail`
// follows the image's id (an image) or the value of "image_id", which the taker writes (an annotation).
struct CocoPiece {
  std::string head, tail;
};

std::string number(int64_t n) { return std::to_string(n); }

// The COCO annotations of one instance image's masks, in the label map's instance order.
std::vector<CocoPiece> coco_annotations(const FrameMasks& frame, const LabelMap& map) {
  std::vector<CocoPiece> out;
  for (const auto& instance : map.instances) {
    auto it = frame.masks.find(instance.id);
    if (it == frame.masks.end()) continue;
    const CocoMask& mask = it->second;
    out.push_back({"{\"area\":" + number(mask.area) + ",\"bbox\":[" + number(mask.bbox.x) + "," + number(mask.bbox.y) +
                       "," + number(mask.bbox.width) + "," + number(mask.bbox.height) +
                       "],\"category_id\":" + number(instance.class_id) + ",\"id\":",
                   ",\"iscrowd\":0,\"olt_instance\":" + json_string(instance.name) +
                       ",\"segmentation\":{\"counts\":" + json_string(mask.counts) + ",\"size\":[" +
                       number(frame.size.height) + "," + number(frame.size.width) + "]}}"});
  }
  return out;
}

// The boxes whose instance has pixels in a frame's masks, by position.
std::vector<uint32_t> shown_boxes(const std::vector<Box>& boxes, const LabelMap& map,
                                  const std::map<uint16_t, CocoMask>& present) {
  std::vector<uint32_t> shown;
  for (size_t k = 0; k < boxes.size(); ++k)
    if (present.count(map.instance_id(boxes[k].instance))) shown.push_back(static_cast<uint32_t>(k));
  return shown;
}

// Image paths relative to the recording's folder (or, for generated recordings, the source's
// artifact), so the dataset can move: COCO readers take the image root as an argument.
std::string image_name(const fs::path& root, const std::string& path) {
  return fs::path(path).lexically_relative(root).generic_string();
}

// One observation's part of the export: its COCO image entry and annotations (ids assigned later,
// in observation order) and its boxes in the sensor frame.
struct ExportFrame {
  bool labeled = false;
  std::string file_name;  ///< the COCO image's
  CocoPiece image;
  std::vector<CocoPiece> annotations;
  std::optional<std::vector<uint32_t>> shown;  ///< the boxes with pixels in it, when sensor boxes are written
};

ExportFrame export_frame(const ExportInputs& in, const ExportConfig& c, size_t i) {
  const Observation& o = in.recording->observations[i];
  ExportFrame f;
  const std::optional<MasksFile> masks = in.masks_file(i);
  if (!masks) return f;  // not labeled (flagged pose)
  // Where this run labeled the frame, its masks as the labeling stage kept them (run_memory.h).
  std::shared_ptr<const FrameMasks> kept =
      masks->sha256.empty() ? nullptr : kept_for_run<FrameMasks>(masks->sha256.hex());
  if (!kept) kept = std::make_shared<const FrameMasks>(read_frame_masks(in.read(masks->path), masks->path));
  const FrameMasks& frame = *kept;
  f.labeled = true;
  if (c.coco) {
    f.file_name = image_name(in.image_root, o.color ? o.color->file() : o.depth.file());
    f.image = {"{\"file_name\":" + json_string(f.file_name) + ",\"height\":" + number(frame.size.height) + ",\"id\":",
               ",\"olt_observation\":" + json_string(o.id) + ",\"olt_sensor\":" + json_string(o.sensor) +
                   ",\"width\":" + number(frame.size.width) + "}"};
    f.annotations = coco_annotations(frame, in.map);
  }
  if (c.sensor_boxes) f.shown = shown_boxes(in.boxes, in.map, frame.masks);
  return f;
}

// The bytes an export frame holds, as kept in memory.
size_t bytes_of(const ExportFrame& f) {
  size_t bytes = sizeof(ExportFrame) + f.file_name.size() + f.image.head.size() + f.image.tail.size();
  for (const auto& a : f.annotations) bytes += sizeof(CocoPiece) + a.head.size() + a.tail.size();
  return bytes + (f.shown ? f.shown->size() * sizeof(uint32_t) : 0);
}

// What every frame's export is made from besides its own masks and images, as a digest.
std::string export_context(const ExportInputs& in, const ExportConfig& c) {
  nlohmann::json instances = nlohmann::json::array();  // the boxes' instances, which say which boxes show
  for (const Box& b : in.boxes) instances.push_back(b.instance);
  return sha256_hex(nlohmann::json{{"map", to_json(in.map)},
                                   {"instances", instances},
                                   {"coco", c.coco},
                                   {"sensor_boxes", c.sensor_boxes},
                                   {"image_root", in.image_root.generic_string()}}
                        .dump());
}

// A frame's export, kept by `olt watch` while its masks and what else it is made from stay the same
// (an edit of one box changes few frames' masks; the others' are neither read nor parsed again).
std::shared_ptr<const ExportFrame> kept_export_frame(const ExportInputs& in, const ExportConfig& c, size_t i,
                                                     KeptPerItem<ExportFrame>& kept) {
  const Observation& o = in.recording->observations[i];
  const std::optional<MasksFile> masks = keeping_memory() ? in.masks_file(i) : std::nullopt;
  if (!masks || masks->sha256.empty())  // not labeled, or nothing kept
    return std::make_shared<const ExportFrame>(export_frame(in, c, i));
  return kept.made_or_before(
      i, o.sensor + "/" + o.id + " " + masks->sha256.hex() + " " + (o.color ? o.color->file() : o.depth.file()),
      [&] { return export_frame(in, c, i); }, [](const ExportFrame& f) { return bytes_of(f); });
}

// The COCO file, made as text frame by frame as the frames come (in observation order, numbered
// so; each frame's entries freed once added): the bytes of the whole document's compact dump
// (nlohmann's objects keep their keys sorted: annotations, categories, images, info), without the
// document in memory as a tree; its annotations and images spooled (held up to a few megabytes).
class CocoText {
 public:
  void add(const ExportFrame& f, ExportResult& result) {
    const int image_id = ++result.images;
    result.coco_images.push_back(f.file_name);
    images_.append((images_.empty() ? "" : ",") + f.image.head + number(image_id) + f.image.tail);
    for (const auto& a : f.annotations)
      annotations_.append((annotations_.empty() ? "" : ",") + a.head + number(++result.annotations) +
                          ",\"image_id\":" + number(image_id) + a.tail);
  }
  std::vector<SpooledText> finish(const ExportInputs& in) {
    nlohmann::json categories = nlohmann::json::array();
    for (const auto& cls : in.map.classes)
      categories.push_back({{"id", cls.id}, {"name", cls.name}, {"supercategory", ""}});
    const nlohmann::json info = {
        {"description", "OLT propagated labels"}, {"version", "1.0"}, {"olt_image_root", in.coco_image_root}};
    std::vector<SpooledText> text(5);
    text[0].append("{\"annotations\":[");
    text[1] = std::move(annotations_);
    text[2].append("],\"categories\":" + categories.dump() + ",\"images\":[");
    text[3] = std::move(images_);
    text[4].append("],\"info\":" + info.dump() + "}\n");
    return text;
  }

 private:
  SpooledText images_, annotations_;
};

}  // namespace

std::string sensor_boxes_text(const ExportResult& result, const SensorBoxes& frame) {
  const Observation& o = result.recording->observations.at(frame.observation);
  const LabelMap& map = result.map;
  nlohmann::json list = nlohmann::json::array();
  const Pose T_sensor_world = result.poses->at(frame.observation).T_world_sensor.inverse();
  for (const uint32_t k : frame.shown) {
    const Box& b = result.boxes.at(k);
    const nlohmann::json p = pose_to_json(T_sensor_world * b.T_world_box);
    list.push_back({{"id", b.id},
                    {"label", b.label},
                    {"class_id", map.class_id(b.label)},
                    {"instance", b.instance},
                    {"instance_id", map.instance_id(b.instance)},
                    {"center", {p[0], p[1], p[2]}},
                    {"size", {b.size.x(), b.size.y(), b.size.z()}},
                    {"rotation", {p[3], p[4], p[5], p[6]}}});
  }
  const nlohmann::json file = {
      {"observation", o.id}, {"sensor", o.sensor}, {"timestamp", o.timestamp}, {"frame", "sensor"}, {"boxes", list}};
  return file.dump(1) + "\n";
}

ExportResult run_export(const ExportInputs& in, const ExportConfig& c) {
  ExportResult result;
  result.recording = in.recording;
  result.poses = in.poses;
  result.labels_yaml = labels_yaml(in.map);
  result.boxes = in.boxes;
  result.map = in.map;
  const auto& observations = in.recording->observations;
  CocoText coco;
  KeptPerItem<ExportFrame> kept(in.kept_name, observations.size(), export_context(in, c));
  result.sensor_boxes.reserve(observations.size());  // of their size: a list grown by doubling holds up to twice
  Progress progress("observations exported", observations.size());
  // In blocks: a block's frames are made in parallel, then taken in order, so only a block's worth
  // of them is held at a time (~10 KB a frame: 100 MB at 10,000 observations); `olt watch` holds
  // what its memory budget allows for the next run besides.
  constexpr size_t kBlock = 256;
  for (size_t begin = 0; begin < observations.size(); begin += kBlock) {
    std::vector<std::shared_ptr<const ExportFrame>> frames(std::min(kBlock, observations.size() - begin));
    parallel_for(frames.size(), [&](size_t k) {
      frames[k] = kept_export_frame(in, c, begin + k, kept);
      progress.advance();
    });
    for (size_t k = 0; k < frames.size(); ++k) {
      const ExportFrame& f = *frames[k];
      if (f.shown) result.sensor_boxes.push_back({static_cast<uint32_t>(begin + k), *f.shown});
      if (c.coco && f.labeled) coco.add(f, result);
      frames[k].reset();  // kept by the process where it keeps them, else freed with the block
    }
  }
  kept.remember_all();
  if (c.coco) result.coco = coco.finish(in);
  result.images_in_cache = in.recording->root.empty();
  return result;
}

namespace {

ExportInputs load(const StageContext& context) {
  ExportInputs in;
  in.recording = shared_recording(context.need("source"));
  in.poses = shared_poses(context.need("poses"));
  check_poses_match(*in.recording, *in.poses, context.stage.id);
  in.boxes = load_boxes(context.need("annotations"));
  const Artifact& labels = context.need("propagate").artifact;
  in.map = label_map_from_json(nlohmann::json::parse(read_file(labels.path("labels.json"))));
  in.masks_file = [&labels, recording = in.recording](size_t i) -> std::optional<MasksFile> {
    const Observation& o = recording->observations[i];
    const std::optional<ListedFile> masks = labels.file(o.sensor + "/masks/" + o.id + ".json");
    if (!masks) return std::nullopt;
    return MasksFile{labels.path(*masks).string(), masks->sha256};
  };
  in.kept_name = context.kept_name("export frames");
  // Paths in the output are relative, so a job's outputs are the same bytes wherever it is checked out.
  const bool generated = in.recording->root.empty();
  in.image_root = generated ? context.need("source").artifact.dir : fs::absolute(in.recording->root);
  in.coco_image_root =
      generated ? "images" : in.image_root.lexically_relative(context.output / context.stage.id).generic_string();
  return in;
}

// The raw bytes of `value`, appended: a part of what a kept value is made from.
template <typename T>
void append_bytes(std::string& to, const T& value) {
  to.append(reinterpret_cast<const char*>(&value), sizeof value);
}

// What a box gives every boxes file it shows in, as a digest: its names, ids, pose and size.
std::string box_digest(const Box& b, const LabelMap& map) {
  std::string made_of = b.id + '\n' + b.label + '\n' + b.instance + '\n';
  append_bytes(made_of, map.class_id(b.label));
  append_bytes(made_of, map.instance_id(b.instance));
  for (int k = 0; k < 16; ++k) append_bytes(made_of, b.T_world_box.matrix()(k));
  for (int k = 0; k < 3; ++k) append_bytes(made_of, b.size(k));
  return sha256_hex(made_of);
}

// An observation's boxes file. A process that keeps memory (`olt watch`) keeps its text by what it is
// made from (the observation, its pose, and the boxes it shows), so that after an edit only the files
// of the frames that show the edited box are made again: making all 10,000 was 4.5 % of a one-box
// cycle at 10,000 observations.
std::string kept_sensor_boxes_text(const SensorBoxes& frame, const ExportResult& result,
                                   const std::vector<std::string>& box_digests, size_t i,
                                   KeptPerItem<std::string>& kept) {
  const auto make = [&] { return sensor_boxes_text(result, frame); };
  if (box_digests.empty()) return make();
  const Observation& o = result.recording->observations[frame.observation];
  std::string made_of = json_string(o.sensor) + json_string(o.id);
  append_bytes(made_of, o.timestamp);
  for (int k = 0; k < 16; ++k) append_bytes(made_of, (*result.poses)[frame.observation].T_world_sensor.matrix()(k));
  for (const uint32_t k : frame.shown) made_of += box_digests.at(k);
  return *kept.made_or_before(i, std::move(made_of), make,
                              [](const std::string& text) { return sizeof(std::string) + text.size(); });
}

nlohmann::json save(const ExportResult& result, const StageContext& context, ArtifactWriter& out) {
  const std::string folder = context.stage.id + "/";
  out.write("labels.yaml", result.labels_yaml);
  out.publish("labels.yaml", folder + "labels.yaml", "labels_yaml");
  const auto observation = [&](size_t i) -> const Observation& {
    return result.recording->observations[result.sensor_boxes[i].observation];
  };
  const auto boxes_file = [&](size_t i) { return observation(i).sensor + "/boxes/" + observation(i).id + ".json"; };
  std::vector<std::string> box_digests;  // none where nothing is kept
  if (keeping_memory())
    for (const Box& b : result.boxes) box_digests.push_back(box_digest(b, result.map));
  // A file per observation, written in parallel; published in observation order.
  KeptPerItem<std::string> kept(context.kept_name("sensor boxes"), result.sensor_boxes.size());
  parallel_for(result.sensor_boxes.size(), [&](size_t i) {
    out.write(boxes_file(i), kept_sensor_boxes_text(result.sensor_boxes[i], result, box_digests, i, kept));
  });
  kept.remember_all();
  for (size_t i = 0; i < result.sensor_boxes.size(); ++i) {
    const Observation& o = observation(i);
    out.publish(boxes_file(i), folder + boxes_file(i), "sensor_boxes", o.sensor, o.id, o.timestamp);
  }
  if (!result.coco.empty()) {
    out.write_pieces("instances.json", [&](const PieceSink& sink) {
      for (const auto& part : result.coco) part.for_each_piece(sink);
    });
    out.publish("instances.json", folder + "instances.json", "coco_instances");
    // A generated recording's images live in the cache: published beside instances.json.
    if (result.images_in_cache)
      for (const std::string& image : result.coco_images) {
        out.refer("images/" + image, context.need("source").artifact, image);
        out.publish("images/" + image, folder + "images/" + image, "coco_image");
      }
  }
  return {{"images", result.images}, {"annotations", result.annotations}};
}

}  // namespace

StageKind export_kind() {
  StageKind kind = make_stage_kind({"export", params(), {"source", "poses", "annotations", "propagate"}, {}, nullptr},
                                   4, nullptr, typed_stage(params(), load, run_export, save));
  kind.reads_output = true;
  return kind;
}

}  // namespace olt
