#include "propagate_frame.h"

#include <algorithm>
#include <functional>
#include <optional>

#include "olt/core/error.h"
#include "olt/core/hash.h"
#include "olt/core/image.h"
#include "olt/core/image_strips.h"
#include "olt/core/json_text.h"
#include "olt/core/process_memory.h"
#include "olt/core/run_memory.h"
#include "olt/formats/cloud_files.h"
#include "olt/formats/coco.h"

namespace olt {
namespace {

constexpr int kFrameVersion = 6;  // bump when a frame's files change for the same key inputs

nlohmann::json box_json(const LabeledBox& b, const LabelMap& map) {
  const LabelClass* c = map.find_class(b.class_id);
  return {{"id", b.box.id},
          {"label", b.box.label},
          {"instance", b.box.instance},
          {"class_id", b.class_id},
          {"instance_id", b.instance_id},
          {"color", c ? nlohmann::json(c->color) : nlohmann::json()},
          {"pose", pose_to_json(b.box.T_world_box)},
          {"size", {b.box.size.x(), b.box.size.y(), b.box.size.z()}},
          {"priority", b.box.priority}};
}

// The bounding rectangle of each id's pixels in a label image.
std::map<uint16_t, cv::Rect> rects_by_id(const cv::Mat& ids) {
  struct Extent {
    int u0 = INT32_MAX, v0 = INT32_MAX, u1 = -1, v1 = -1;
  };
  std::vector<Extent> extents;  // by id; ids are small (1..instances)
  for (int v = 0; v < ids.rows; ++v) {
    const uint16_t* row = ids.ptr<uint16_t>(v);
    for (int u = 0; u < ids.cols;) {  // run by run: label images are long runs of one id
      const uint16_t id = row[u];
      const int first = u;
      while (u < ids.cols && row[u] == id) ++u;
      if (id == kUnlabeled || id == kNoDepth) continue;
      if (id >= extents.size()) extents.resize(id + 1u);
      Extent& e = extents[id];
      e.u0 = std::min(e.u0, first), e.u1 = std::max(e.u1, u - 1);
      e.v0 = std::min(e.v0, v), e.v1 = std::max(e.v1, v);
    }
  }
  std::map<uint16_t, cv::Rect> rects;
  for (size_t id = 0; id < extents.size(); ++id)
    if (extents[id].u1 >= 0)
      rects[static_cast<uint16_t>(id)] = cv::Rect(extents[id].u0, extents[id].v0, extents[id].u1 - extents[id].u0 + 1,
                                                  extents[id].v1 - extents[id].v0 + 1);
  return rects;
}

// A box's entry in the frame's record, as dump(1) writes it two levels deep (keys sorted).
std::string box_record_text(const LabeledBox& b, const BoxInFrame& seen,
                            const std::map<uint16_t, cv::Rect>& depth_rects,
                            const std::map<uint16_t, cv::Rect>& color_rects) {
  std::string t = "  {\n";
  const auto field = [&](const char* key, const std::string& value) {
    t += "   \"";
    t += key;
    t += "\": " + value + ",\n";
  };
  const auto rect = [&](const char* key, const cv::Rect& r) {
    field(key, "[\n    " + std::to_string(r.x) + ",\n    " + std::to_string(r.y) + ",\n    " + std::to_string(r.width) +
                   ",\n    " + std::to_string(r.height) + "\n   ]");
  };
  if (auto it = color_rects.find(b.instance_id); it != color_rects.end()) rect("bbox_color", it->second);
  if (auto it = depth_rects.find(b.instance_id); it != depth_rects.end()) rect("bbox_depth", it->second);
  field("bottom_pixels", std::to_string(seen.bottom_pixels));
  field("box", json_string(b.box.id));
  if (!seen.bbox.empty()) rect("box_bbox_depth", seen.bbox);
  field("class_id", std::to_string(b.class_id));
  field("covered_pixels", std::to_string(seen.covered_pixels));
  field("instance", json_string(b.box.instance));
  field("instance_id", std::to_string(b.instance_id));
  field("label", json_string(b.box.label));
  field("labeled_pixels", std::to_string(seen.labeled_pixels));
  const double visible = static_cast<double>(seen.labeled_pixels) / seen.covered_pixels;
  return t + "   \"visible_fraction\": " + nlohmann::json(visible).dump() + "\n  }";
}

}  // namespace

std::string frame_record_text(const FrameInputs& f, const FrameLabels& labels, const FrameMasks& masks,
                              const ColorLabels* color) {
  // Both per instance (what a detector's box is: its mask's), and the box's own pixels in depth as
  // box_bbox_depth.
  std::map<uint16_t, cv::Rect> depth_rects;
  for (const auto& [id, mask] : masks.masks) depth_rects[id] = mask.bbox;
  // Registered depth: the colour labels are the depth labels' own images, so their rectangles too.
  const bool color_is_depth = color && color->instance_ids.data == labels.instance_ids.data;
  const auto color_rects = !color           ? std::map<uint16_t, cv::Rect>()
                           : color_is_depth ? depth_rects
                                            : rects_by_id(color->instance_ids);
  // As nlohmann's dump(1) writes the record (keys sorted): made as text, since building and dumping
  // the document was a tenth of relabeling a TUM frame in place.
  std::string t = "{\n \"ambiguous_pixels\": " + std::to_string(labels.ambiguous_pixels) + ",\n \"boxes\": ";
  bool any = false;
  for (size_t k = 0; k < f.boxes.size(); ++k) {
    if (labels.boxes[k].covered_pixels == 0) continue;
    t += any ? ",\n" : "[\n";
    t += box_record_text(f.boxes[k], labels.boxes[k], depth_rects, color_rects);
    any = true;
  }
  t += any ? "\n ]" : "[]";
  t += ",\n \"labeled_pixels\": " + std::to_string(labels.labeled_pixels) +
       ",\n \"observation\": " + json_string(f.observation.id) +
       ",\n \"pose\": {\n  \"flag\": " + json_string(f.pose.flag) + ",\n  \"quality\": ";
  append_nested(t, to_json(f.pose.quality), 2);
  t += std::string(",\n  \"valid\": ") + (f.pose.valid ? "true" : "false") +
       "\n },\n \"sensor\": " + json_string(f.observation.sensor) +
       ",\n \"timestamp\": " + nlohmann::json(f.observation.timestamp).dump() +
       ",\n \"valid_pixels\": " + std::to_string(labels.valid_pixels) + "\n}";
  return t;
}

FrameCounts frame_counts_of(const FrameInputs& f, const FrameLabels& labels,
                            const std::map<std::string, uint32_t>& positions) {
  FrameCounts counts{labels.labeled_pixels, labels.valid_pixels, labels.ambiguous_pixels, {}};
  for (size_t k = 0; k < f.boxes.size(); ++k) {
    const BoxInFrame& seen = labels.boxes[k];
    if (seen.covered_pixels == 0) continue;  // as frame_record_text leaves it out
    const auto at = positions.find(f.boxes[k].box.id);
    if (at != positions.end()) counts.boxes.push_back({at->second, seen.labeled_pixels, seen.bottom_pixels});
  }
  counts.boxes.shrink_to_fit();  // 10,000 frames' lists are kept
  return counts;
}

const Names<CloudFiles>& cloud_file_names() {
  static const Names<CloudFiles> names = {
      {"none", CloudFiles::none}, {"pcd", CloudFiles::pcd}, {"ply", CloudFiles::ply}};
  return names;
}

std::string name_of(CloudFiles files) { return name_in(cloud_file_names(), files); }

RecordParts record_parts(const std::vector<LabeledBox>& ordered, const Calibration& calibration, const LabelMap& map,
                         const PropagateConfig& c) {
  RecordParts parts;
  std::vector<std::pair<std::string, uint32_t>> ids;
  for (size_t k = 0; k < ordered.size(); ++k) {
    parts.boxes.push_back(json_string(ordered[k].box.id) + ":\"" + sha256_hex(box_json(ordered[k], map).dump()) + "\"");
    ids.emplace_back(ordered[k].box.id, static_cast<uint32_t>(k));
  }
  std::sort(ids.begin(), ids.end());  // as nlohmann orders an object's keys
  parts.box_ranks.resize(ordered.size());
  for (size_t r = 0; r < ids.size(); ++r) parts.box_ranks[ids[r].second] = static_cast<uint32_t>(r);
  for (const auto& [sensor, cal] : calibration) parts.calibrations[sensor] = sha256_hex(to_json(cal).dump());
  parts.color_labels =
      (c.color_labels ? nlohmann::json{c.color_fill_px, c.color_fill_tolerance_m} : nlohmann::json()).dump();
  parts.frame_version = std::to_string(kFrameVersion);
  parts.overlays = nlohmann::json(c.overlays).dump();
  parts.point_clouds = nlohmann::json(name_of(c.point_clouds)).dump();
  parts.color = c.overlays || c.color_labels || c.point_clouds != CloudFiles::none;
  return parts;
}

std::string pose_digest(const ObservationPose& pose) {
  return sha256_hex(to_json(std::vector<ObservationPose>{pose}).dump());
}

std::string frame_inputs_record(const Observation& o, const std::string& pose_sha256,
                                const std::vector<uint32_t>& in_view, const RecordParts& parts) {
  std::vector<uint32_t> by_id = in_view;
  std::sort(by_id.begin(), by_id.end(),
            [&](uint32_t a, uint32_t b) { return parts.box_ranks[a] < parts.box_ranks[b]; });
  std::string boxes;
  for (size_t k = 0; k < by_id.size(); ++k) boxes += (k ? "," : "") + parts.boxes[by_id[k]];
  const std::string color = parts.color && o.color ? o.color->sha256.hex() : "";
  // Every key, in nlohmann's order.
  return "{\"boxes\":{" + boxes + "},\"calibration\":\"" + parts.calibrations.at(o.sensor) + "\",\"color\":\"" + color +
         "\",\"color_labels\":" + parts.color_labels + ",\"depth\":\"" + o.depth.sha256.hex() +
         "\",\"frame_version\":" + parts.frame_version + ",\"overlays\":" + parts.overlays +
         ",\"point_clouds\":" + parts.point_clouds + ",\"pose\":\"" + pose_sha256 + "\"}";
}

namespace {

// The bytes of the previous frame's file `name`, if it has them.
const std::string* previous_file(const LabeledFrame* previous, const std::string& name) {
  if (!previous) return nullptr;
  const auto it = previous->files.find(name);
  return it == previous->files.end() ? nullptr : &it->second;
}

// Label image `name` written, and kept in `made`: spliced from the previous frame's PNG where it has
// it (only the bands of the rows that differ from the previous labels, `changed_rows`, encoded again),
// else encoded whole.
void write_label_png(ArtifactWriter& out, const std::string& name, const cv::Mat& now, const LabeledFrame* previous,
                     const std::vector<bool>& changed_rows, LabeledFrame& made) {
  const std::string* kept = previous_file(previous, name);
  const std::vector<uint32_t>* sums = nullptr;
  if (kept)
    if (const auto it = previous->png_band_sums.find(name); it != previous->png_band_sums.end()) sums = &it->second;
  LabelPng png = sums ? splice_label_png(*kept, *sums, now, changed_rows) : label_png(now);
  out.write(name, png.bytes);
  made.files[name] = std::move(png.bytes);
  made.png_band_sums[name] = std::move(png.band_sums);
}

// The previous frame's class and instance labels, as far as the frame's files are made from them: the
// images whole, or, where the frame was labeled over them, what was kept of them (the rows labeled
// again, where rows are compared below; the others undefined).
struct LabelsBefore {
  cv::Mat class_ids, instance_ids;
};

// Per row, whether the frame's class and instance labels differ from the previous frame's: compared
// only in the rows the frame was relabeled in (the others are the previous ones), where it was.
struct DifferingRows {
  std::vector<bool> classes, instances;
};

DifferingRows differing_label_rows(const FrameLabels& now, const LabeledFrame* previous, const LabelsBefore& before) {
  if (!previous) return {};
  return {differing_rows(now.class_ids, before.class_ids, now.rows_relabeled),
          differing_rows(now.instance_ids, before.instance_ids, now.rows_relabeled)};
}

bool any(const std::vector<bool>& flags) { return std::find(flags.begin(), flags.end(), true) != flags.end(); }

}  // namespace

size_t bytes_of(const LabeledFrame& frame) {
  size_t bytes = 0;
  for (const cv::Mat* image :
       {&frame.labels.class_ids, &frame.labels.instance_ids, &frame.color.class_ids, &frame.color.instance_ids})
    bytes += image->total() * image->elemSize();
  for (const auto& [name, file] : frame.files) bytes += file.size();
  for (const auto& [name, sums] : frame.png_band_sums) bytes += sums.size() * sizeof(uint32_t);
  bytes += bytes_of(frame.masks);
  for (const Footprint& f : frame.labels.footprints)
    bytes += sizeof(Footprint) + f.outline.size() * sizeof(cv::Point2f);
  return bytes + frame.labels.rows_relabeled.size() / 8;
}

bool only_boxes_changed(const nlohmann::json& before, const nlohmann::json& now) {
  if (!before.is_object() || !now.is_object() || before.size() != now.size()) return false;
  for (const auto& [field, value] : now.items())
    if (field != "boxes" && (!before.contains(field) || before.at(field) != value)) return false;
  return true;
}

namespace {

// The depth image of a frame, checked against its calibration.
cv::Mat frame_depth(const FrameInputs& f) {
  const cv::Mat depth = remembered_grey16(f.observation.depth.file());  // read only: it may be shared
  const Intrinsics& camera = f.calibration.depth;
  if (depth.cols != camera.width || depth.rows != camera.height)
    throw InputError(f.observation.depth.file(), "depth image is " + std::to_string(depth.cols) + "x" +
                                                     std::to_string(depth.rows) + ", the calibration says " +
                                                     std::to_string(camera.width) + "x" +
                                                     std::to_string(camera.height));
  return depth;
}

// Whether `image`'s pixels are held by its header alone (no other cv::Mat shares them).
bool sole_holder(const cv::Mat& image) { return image.u && image.u->refcount == 1; }

// The frame's labels, relabeled in place from `previous` where that is less work, else afresh, and
// the previous labels as far as its files need them. `label_over_previous`: nobody reads previous's
// images after this frame, so it is relabeled in them (only the rows it labels again copied first),
// not in copies of them whole (1.2 MB at 640x480: half of relabeling a frame in place after a one-box
// edit, by perf in the twenty-first session).
std::pair<FrameLabels, bool> labels_of(const FrameInputs& f, const cv::Mat& depth, const LabeledFrame* previous,
                                       bool label_over_previous, LabelsBefore& before) {
  const Pose& pose = f.pose.T_world_sensor;
  if (previous) {
    const FrameLabels& was = previous->labels;
    const bool over = label_over_previous && sole_holder(was.class_ids) && sole_holder(was.instance_ids);
    before = {was.class_ids, was.instance_ids};
    const ImagesToRelabel images = [&](const std::vector<bool>& rows) {
      if (!over) return std::pair{was.class_ids.clone(), was.instance_ids.clone()};
      before = {rows_of(was.class_ids, rows), rows_of(was.instance_ids, rows)};
      return std::pair{was.class_ids, was.instance_ids};
    };
    if (auto in_place = relabel_depth_image(depth, f.calibration, f.view, pose, f.boxes, previous->boxes, was, images))
      return {std::move(*in_place), true};
  }
  return {label_depth_image(depth, f.calibration, f.view, pose, f.boxes), false};
}

// The label files (class, instance, the export's masks, the colour labels where the colour camera
// is not the depth camera) into `out` and `made.files`; the previous bytes where the labels came out
// the same. Returns the colour labels, if the frame has them.
std::optional<ColorLabels> write_label_files(const FrameInputs& f, const PropagateConfig& c, const cv::Mat& depth,
                                             const LabeledFrame* previous, const LabelsBefore& before,
                                             const DifferingRows& differ, LabeledFrame& made, ArtifactWriter& out) {
  const FrameLabels& labels = made.labels;
  const auto write = [&](const std::string& name, const cv::Mat& now, const std::vector<bool>& changed_rows) {
    write_label_png(out, name, now, previous, changed_rows, made);
  };
  write("class.png", labels.class_ids, differ.classes);
  write("instance.png", labels.instance_ids, differ.instances);
  // The instances' masks: the previous ones where the instances are the same, else found again only
  // for the instances whose pixels changed.
  const std::vector<uint16_t> not_instances = {kUnlabeled, kNoDepth};
  const std::string* masks_text = previous_file(previous, "masks.json");
  if (masks_text && !any(differ.instances)) {
    made.masks = previous->masks;
    made.files["masks.json"] = *masks_text;
  } else {
    made.masks = previous ? frame_masks_changed(labels.instance_ids, not_instances, previous->masks,
                                                before.instance_ids, differ.instances)
                          : frame_masks(labels.instance_ids, not_instances);
    made.files["masks.json"] = frame_masks_text(made.masks);
  }
  out.write("masks.json", made.files["masks.json"]);
  // For the export, which would read the file and parse it next.
  if (const size_t bytes = sizeof(FrameMasks) + bytes_of(made.masks); run_memory_room() >= bytes)
    keep_for_run<FrameMasks>(sha256_hex(made.files["masks.json"]), std::make_shared<const FrameMasks>(made.masks),
                             bytes);
  if (!c.color_labels || !f.observation.color) return std::nullopt;
  // Registered depth: the colour labels are the depth labels, and the stage refers to class.png and
  // instance.png for them (two files fewer to create).
  if (color_is_depth_camera(f.calibration)) return ColorLabels{labels.class_ids, labels.instance_ids};
  made.color = label_color_image(labels, depth, f.calibration, f.view, c.color_fill_px, c.color_fill_tolerance_m);
  // Carried to the colour camera afresh: compared row by row.
  write("class_color.png", made.color.class_ids,
        previous ? differing_rows(made.color.class_ids, previous->color.class_ids) : std::vector<bool>());
  write("instance_color.png", made.color.instance_ids,
        previous ? differing_rows(made.color.instance_ids, previous->color.instance_ids) : std::vector<bool>());
  return made.color;
}

}  // namespace

LabeledFrame label_frame(const FrameInputs& f, const nlohmann::json& record, const PropagateConfig& c,
                         const LabelMap& map, const LabeledFrame* previous, bool label_over_previous,
                         ArtifactWriter& out) {
  const Observation& o = f.observation;
  const SensorCalibration& cal = f.calibration;
  const cv::Mat depth = frame_depth(f);
  LabelsBefore before;
  auto [labels, in_place] = labels_of(f, depth, previous, label_over_previous, before);
  LabeledFrame made{record, f.boxes, std::move(labels), {}, {}, {}, {}, in_place};
  const DifferingRows differ = differing_label_rows(made.labels, previous, before);
  const std::optional<ColorLabels> color_labels = write_label_files(f, c, depth, previous, before, differ, made, out);
  out.write("frame.json",
            frame_record_text(f, made.labels, made.masks, color_labels ? &*color_labels : nullptr) + "\n");
  const cv::Mat color =
      (c.overlays || c.point_clouds != CloudFiles::none) && o.color ? remembered_color(o.color->file()) : cv::Mat();
  if (c.point_clouds == CloudFiles::pcd)
    write_labeled_pcd(out.path("cloud.pcd"), labeled_cloud(made.labels, depth, color, cal, f.view));
  if (c.point_clouds == CloudFiles::ply)
    write_labeled_ply(out.path("cloud.ply"), labeled_cloud(made.labels, depth, color, cal, f.view));
  if (c.overlays) {
    // After an edit, drawn and encoded again only in the strips where it changed.
    const std::string* kept = previous_file(previous, "overlay.jpg");
    const std::vector<bool> rows =
        kept ? whole_strips(overlay_rows_changed(differ.classes, f.boxes, previous->boxes, cal, f.pose.T_world_sensor),
                            jpeg_strip_rows(3))  // overlays are colour
             : std::vector<bool>();
    out.write("overlay.jpg",
              made.files["overlay.jpg"] = redrawn_jpeg_strips(kept, rows, [&](const std::vector<bool>& r) {
                return render_overlay(color, depth, made.labels, map, f.boxes, cal, f.pose.T_world_sensor, r);
              }));
  }
  return made;
}

}  // namespace olt
