// `propagate`: per observation with a valid pose, class and instance images (16-bit PNG, depth
// resolution), a frame record (JSON: every box in view, its pixels, visible fraction and
// rectangle; the pose's quality) and an overlay for people; the label map (labels.json) for the
// whole dataset; for the report, frame_pixels.json ({"SENSOR/OBSERVATION": [labeled pixels, depth
// pixels]} of every labeled frame: one file rather than every frame's record).
//
// Each frame is a unit cached on its own by the runtime, keyed by what its labels depend on: its
// depth (and colour) digest, its pose, its sensor's calibration, the parameters and only the boxes
// it can see. After an annotation edit, only frames that see the old or the new box are labeled
// again; the others are taken from the cache.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <functional>
#include <mutex>
#include <optional>
#include <utility>

#include "box_checks.h"
#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/parallel.h"
#include "olt/core/process_memory.h"
#include "olt/propagate/propagate.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
#include "propagate_frame.h"

namespace olt {
namespace {

std::shared_ptr<const Params<PropagateConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<PropagateConfig>>();
    t->int_map("class_ids", &PropagateConfig::class_ids, between(1, 65534), "fixed class ids by class name")
        .boolean("overlays", &PropagateConfig::overlays, "write an overlay JPEG per observation")
        .boolean("color_labels", &PropagateConfig::color_labels, "also write labels at colour resolution")
        .integer("color_fill_px", &PropagateConfig::color_fill_px, between(0, 10),
                 "fill colour pixels without a depth point from this far (0 = no_depth)")
        .number("color_fill_tolerance_m", &PropagateConfig::color_fill_tolerance_m, positive(),
                "fill only from the front surface: within this depth of the nearest, metres")
        .choice("point_clouds", &PropagateConfig::point_clouds, cloud_file_names(),
                "a labeled point cloud per observation (sensor frame)")
        .boolean("keep_flagged", &PropagateConfig::keep_flagged, "also label observations with a flagged pose");
    return t;
  }();
  return p;
}

// Every pose's digest, as frames' records name them; kept by `olt watch` by the poses file's digest
// (an edit of a box leaves the poses alone: 2 % of a watch cycle at 10,000 observations).
std::shared_ptr<const std::vector<std::string>> kept_pose_digests(const StageInput& input,
                                                                  const std::vector<ObservationPose>& poses) {
  const std::optional<ListedFile> file = input.artifact.file("poses.json");
  const std::string digest = file ? file->sha256.hex() : "";
  return remembered_or_made<std::vector<std::string>>(
      "pose digests of " + input.stage_id, digest,
      [&] {
        std::vector<std::string> digests(poses.size());
        parallel_for(poses.size(), [&](size_t i) { digests[i] = pose_digest(poses[i]); });
        return digests;
      },
      [](const std::vector<std::string>& d) { return d.size() * (sizeof(std::string) + 64); });
}

// Where an observation's camera is: its calibration, its rays, the world in its frame.
struct FrameCamera {
  const SensorCalibration* calibration = nullptr;
  const DepthView* view = nullptr;
  Pose T_sensor_world = Pose::Identity();
};

// Per box, per observation, whether the observation's camera (`camera(i)`; none where its pose is
// not to be labeled) sees the box (box_in_view). `olt watch` keeps each box's list under `names[k]`
// with what it is found from (`made_of[k]`: the box's digest, the recording's, the calibration's and
// the poses' artifacts): after an edit only the boxes it changed are looked for, in one pass over the
// frames (at 10,000 observations a dozen boxes were 120,000 footprints a cycle).
std::vector<std::shared_ptr<const std::vector<char>>> frames_seeing(
    const std::vector<LabeledBox>& boxes, const std::vector<std::string>& names,
    const std::vector<std::string>& made_of, size_t observations,
    const std::function<std::optional<FrameCamera>(size_t)>& camera) {
  std::vector<std::shared_ptr<const std::vector<char>>> seeing(boxes.size());
  std::vector<size_t> missing;
  for (size_t k = 0; k < boxes.size(); ++k) {
    if (keeping_memory()) seeing[k] = remembered_from<std::vector<char>>(names[k], made_of[k]);
    if (!seeing[k]) missing.push_back(k);
  }
  if (missing.empty()) return seeing;
  std::vector<std::vector<char>> found(missing.size(), std::vector<char>(observations, 0));
  parallel_for(observations, [&](size_t i) {
    const std::optional<FrameCamera> c = camera(i);
    if (!c) return;
    for (size_t m = 0; m < missing.size(); ++m)
      found[m][i] = box_in_view(boxes[missing[m]], *c->calibration, *c->view, c->T_sensor_world);
  });
  for (size_t m = 0; m < missing.size(); ++m) {
    auto list = std::make_shared<const std::vector<char>>(std::move(found[m]));
    if (keeping_memory()) remember_from<std::vector<char>>(names[missing[m]], made_of[missing[m]], list, list->size());
    seeing[missing[m]] = std::move(list);
  }
  return seeing;
}

// The stage's inputs, loaded, and per observation with a usable pose the frame to label: a unit
// whose record covers only the boxes it can see.
class PropagateWork : public UnitWork {
 public:
  explicit PropagateWork(const StageContext& ctx);
  PropagateWork(const PropagateWork&) = delete;  // frame(i) refers into the members
  PropagateWork& operator=(const PropagateWork&) = delete;
  const std::vector<std::optional<Unit>>& units() const override { return units_; }
  std::string record(size_t i) const override {
    return records_.read(record_places_[i].offset, record_places_[i].bytes);
  }
  bool run(size_t i, ArtifactWriter& out) const override;
  void take(size_t i, const Artifact& entry, ArtifactWriter& out) override;
  nlohmann::json assemble(const StageContext& ctx, ArtifactWriter& out) override;

 private:
  void publish_frame(const Observation& o, const std::string& stage_id, ArtifactWriter& out) const;
  FrameInputs frame(size_t i) const;

  PropagateConfig config_;
  std::shared_ptr<const Recording> recording_;  ///< shared with the stages after this one
  Calibration calibration_;
  std::shared_ptr<const std::vector<ObservationPose>> poses_;
  std::vector<Box> boxes_;
  std::map<std::string, uint32_t> box_positions_;  ///< by id: frame counts name boxes by position
  LabelMap map_;
  std::map<std::string, std::shared_ptr<const DepthView>> views_;
  std::vector<LabeledBox> ordered_;  ///< the boxes in priority order
  /// Per observation, the positions in ordered_ of the boxes in its view (a few bytes a frame, not
  /// copies of the boxes: 10,000 frames); none when its pose is flagged.
  std::vector<std::optional<std::vector<uint32_t>>> in_view_;
  std::vector<std::optional<Unit>> units_;
  /// The units' records, a megabyte held and the rest in a temporary file (SpooledText), and where
  /// each is there.
  SpooledText records_;
  struct RecordPlace {
    uint64_t offset = 0;
    uint32_t bytes = 0;
  };
  std::vector<RecordPlace> record_places_;
  std::vector<std::optional<FrameCounts>> counts_;  ///< per observation, from its frame's record once taken
  /// Per observation labeled by this run, its counts from its labels, until taken: the runtime takes
  /// a unit on the thread that ran it, right after (olt/runtime's find_or_run), so each slot is one
  /// thread's at a time. Its record is not parsed again (2 % of a TUM watch cycle after a one-box edit).
  mutable std::vector<std::optional<FrameCounts>> labeled_counts_;
  std::string memory_name_;  ///< what this process keeps of its frames is named after the job and stage
  /// ... and its entries' counts, by entry, after the boxes' order too (counts name boxes by position)
  std::unique_ptr<KeptPerItem<FrameCounts>> kept_counts_;
};

PropagateWork::PropagateWork(const StageContext& ctx) {
  config_ = params()->from_json(ctx.stage.params);
  recording_ = shared_recording(ctx.need("source"));
  calibration_ = load_calibration(ctx.need("calibrate"));
  poses_ = shared_poses(ctx.need("poses"));
  check_poses_match(*recording_, *poses_, ctx.stage.id);
  boxes_ = load_boxes(ctx.need("annotations"));
  box_positions_ = box_positions(boxes_);
  map_ = make_label_map(boxes_, config_.class_ids);
  ordered_ = prioritized_boxes(boxes_, map_);
  for (const auto& [sensor, cal] : calibration_) views_[sensor] = shared_depth_view(cal.depth);
  const auto& observations = recording_->observations;
  const RecordParts parts = record_parts(ordered_, calibration_, map_, config_);
  const auto pose_digests = kept_pose_digests(ctx.need("poses"), *poses_);
  memory_name_ = ctx.kept_name("labeled-frame") + ":";
  std::string order;
  for (const auto& b : boxes_) order += json_string(b.id) + ",";
  kept_counts_ =
      std::make_unique<KeptPerItem<FrameCounts>>(ctx.kept_name("frame-counts"), observations.size(), sha256_hex(order));
  in_view_.resize(observations.size());
  units_.resize(observations.size());
  record_places_.resize(observations.size());
  counts_.resize(observations.size());
  labeled_counts_.resize(observations.size());
  const auto usable = [&](size_t i) { return (*poses_)[i].valid || config_.keep_flagged; };
  const std::string inputs = ctx.need("source").artifact.digest + ":" + ctx.need("calibrate").artifact.digest + ":" +
                             ctx.need("poses").artifact.digest + (config_.keep_flagged ? ":flagged" : "");
  std::vector<std::string> names, made_of;
  for (size_t k = 0; k < ordered_.size(); ++k) {
    names.push_back(ctx.kept_name("frames seeing") + ":" + json_string(ordered_[k].box.id));
    made_of.push_back(inputs + ":" + parts.boxes[k]);
  }
  const auto seeing =
      frames_seeing(ordered_, names, made_of, observations.size(), [&](size_t i) -> std::optional<FrameCamera> {
        if (!usable(i)) return std::nullopt;
        const std::string& sensor = observations[i].sensor;
        return FrameCamera{&calibration_.at(sensor), views_.at(sensor).get(), (*poses_)[i].T_world_sensor.inverse()};
      });
  std::mutex spooling;
  // Each frame's own slots, the same on any thread; its record appended to the spool under the lock,
  // in any order, and found by its place.
  parallel_for(observations.size(), [&](size_t i) {
    const Observation& o = observations[i];
    if (!usable(i)) return;
    auto& in_view = in_view_[i].emplace();
    for (size_t k = 0; k < ordered_.size(); ++k)
      if ((*seeing[k])[i]) in_view.push_back(static_cast<uint32_t>(k));
    const std::string record = frame_inputs_record(o, (*pose_digests)[i], in_view, parts);
    units_[i] = unit_of(o.sensor + "/" + o.id, record);
    const std::lock_guard<std::mutex> lock(spooling);
    record_places_[i] = {records_.size(), static_cast<uint32_t>(record.size())};
    records_.append(record);
  });
}

FrameInputs PropagateWork::frame(size_t i) const {
  const Observation& o = recording_->observations[i];
  FrameInputs f{o, (*poses_)[i], calibration_.at(o.sensor), *views_.at(o.sensor), {}};
  for (uint32_t k : *in_view_[i]) f.boxes.push_back(ordered_[k]);
  return f;
}

// A frame labeled again after an edit starts from the frame as this process labeled it before, when
// it kept it (`olt watch`) and only the frame's boxes changed since; what it labels now is kept for
// the next edit. The frame before is taken out of what is kept: where nothing else holds it, it is
// relabeled in its own images (a frame that fails, or whose depth cannot be read, is labeled afresh
// next time).
bool PropagateWork::run(size_t i, ArtifactWriter& out) const {
  const std::string name = memory_name_ + units_[i]->name;
  const auto before = taken<LabeledFrame>(name);
  const nlohmann::json inputs = nlohmann::json::parse(record(i));
  const bool from_before = before && only_boxes_changed(before->record, inputs);
  const FrameInputs f = frame(i);
  LabeledFrame labeled =
      label_frame(f, inputs, config_, map_, from_before ? before.get() : nullptr, before.use_count() == 1, out);
  labeled_counts_[i] = frame_counts_of(f, labeled.labels, box_positions_);
  const bool in_place = labeled.in_place;  // not where more than half its image changed: afresh
  if (keeping_memory()) {
    const size_t bytes = bytes_of(labeled);
    remember<LabeledFrame>(name, std::make_shared<const LabeledFrame>(std::move(labeled)), bytes);
  }
  return in_place;
}

// The frame's files, referred to in the stage's artifact.
void refer_frame(const Observation& o, const Artifact& frame, const PropagateConfig& c, ArtifactWriter& out) {
  const std::string stem = o.sensor + "/";
  out.refer(stem + "class/" + o.id + ".png", frame, "class.png");
  out.refer(stem + "instance/" + o.id + ".png", frame, "instance.png");
  out.refer(stem + "frames/" + o.id + ".json", frame, "frame.json");
  out.refer(stem + "masks/" + o.id + ".json", frame, "masks.json");  // not published: the export's
  if (c.overlays) out.refer(overlay_file(o.sensor, o.id), frame, "overlay.jpg");
  if (c.point_clouds != CloudFiles::none)
    out.refer(stem + "clouds/" + o.id + "." + name_of(c.point_clouds), frame, "cloud." + name_of(c.point_clouds));
  if (c.color_labels && o.color) {
    // An entry without colour label files is registered depth's: its depth labels are the colour ones.
    const bool own = frame.file("class_color.png").has_value();
    out.refer(stem + "class_color/" + o.id + ".png", frame, own ? "class_color.png" : "class.png");
    out.refer(stem + "instance_color/" + o.id + ".png", frame, own ? "instance_color.png" : "instance.png");
  }
}

void PropagateWork::publish_frame(const Observation& o, const std::string& stage_id, ArtifactWriter& out) const {
  const std::string stem = o.sensor + "/", output = stage_id + "/" + stem;
  auto publish = [&](const std::string& folder, const std::string& extension, const std::string& kind) {
    const std::string file = folder + "/" + o.id + extension;
    out.publish(stem + file, output + file, kind, o.sensor, o.id, o.timestamp);
  };
  publish("class", ".png", "class_label");
  publish("instance", ".png", "instance_label");
  publish("frames", ".json", "frame_labels");
  if (config_.overlays) publish("overlay", ".jpg", "overlay");
  if (config_.point_clouds != CloudFiles::none) publish("clouds", "." + name_of(config_.point_clouds), "labeled_cloud");
  if (config_.color_labels && o.color) {
    publish("class_color", ".png", "class_label_color");
    publish("instance_color", ".png", "instance_label_color");
  }
}

// A frame's files referred to from the stage's artifact, and its counts, kept for the summary: from
// its labels where this run labeled it, else read from its record. An entry never changes (its key
// names its content), so a process that keeps memory keeps the counts by the entry's key: reading
// 10,000 records again was 4 % of an `olt watch` cycle after a one-box edit at 10,000 observations.
void PropagateWork::take(size_t i, const Artifact& entry, ArtifactWriter& out) {
  refer_frame(recording_->observations[i], entry, config_, out);
  // Counted by run(i) just before, where this run labeled the frame.
  std::optional<FrameCounts> labeled = std::exchange(labeled_counts_[i], std::nullopt);
  const auto read = [&] {
    return labeled ? std::move(*labeled) : frame_counts(read_file(entry.path("frame.json")), box_positions_);
  };
  const auto bytes = [](const FrameCounts& c) { return sizeof c + c.boxes.capacity() * sizeof(FrameCounts::Box); };
  counts_[i] = keeping_memory() ? *kept_counts_->made_or_before(i, entry.key, read, bytes) : read();
}

nlohmann::json PropagateWork::assemble(const StageContext& ctx, ArtifactWriter& out) {
  kept_counts_->remember_all();                     // every unit taken
  std::vector<std::optional<Unit>>().swap(units_);  // run, taken and recorded: let go
  records_ = SpooledText();
  std::vector<RecordPlace>().swap(record_places_);
  const auto& observations = recording_->observations;
  const auto& counts = counts_;
  std::map<std::string, std::pair<int64_t, int64_t>> per_class;  // name -> (pixels, frames)
  int labeled_frames = 0;
  int64_t ambiguous = 0, labeled_pixels = 0, depth_pixels = 0;
  for (size_t i = 0; i < observations.size(); ++i) {
    if (!counts[i]) continue;
    ++labeled_frames;
    ambiguous += counts[i]->ambiguous_pixels;
    labeled_pixels += counts[i]->labeled_pixels;
    depth_pixels += counts[i]->depth_pixels;
    std::map<std::string, int64_t> seen;
    for (const auto& b : counts[i]->boxes) seen[boxes_[b.box].label] += b.labeled_pixels;
    for (const auto& [name, pixels] : seen) {
      per_class[name].first += pixels;
      per_class[name].second += pixels > 0;
    }
    publish_frame(observations[i], ctx.stage.id, out);
  }
  // Every labeled frame's pixel counts in one file, for the report (rather than its 10,000 records).
  nlohmann::json frame_pixels = nlohmann::json::object();
  for (size_t i = 0; i < observations.size(); ++i)
    if (counts[i])
      frame_pixels[observations[i].sensor + "/" + observations[i].id] = {counts[i]->labeled_pixels,
                                                                         counts[i]->depth_pixels};
  out.write("frame_pixels.json", frame_pixels.dump() + "\n");
  std::vector<Eigen::Vector3d> cameras;
  double max_depth_m = 0;
  for (size_t i = 0; i < observations.size(); ++i)
    if (in_view_[i]) cameras.push_back((*poses_)[i].T_world_sensor.translation());
  for (const auto& [sensor, cal] : calibration_) max_depth_m = std::max(max_depth_m, cal.max_depth_m);
  const BoxChecks checks = check_boxes(boxes_, counts, cameras, max_depth_m);
  for (const auto& warning : checks.warnings) spdlog::warn("{}: {}", ctx.stage.id, warning);
  nlohmann::json labels = to_json(map_);
  labels["boxes"] = checks.boxes;
  labels["instance_counts"] = checks.instances;
  labels["warnings"] = checks.warnings;
  out.write("labels.json", labels.dump(1) + "\n");
  out.publish("labels.json", "labels.json", "label_map");
  nlohmann::json classes = nlohmann::json::object();
  for (const auto& [name, counts] : per_class) classes[name] = {{"pixels", counts.first}, {"frames", counts.second}};
  nlohmann::json summary = {
      {"observations_labeled", labeled_frames}, {"observations_skipped", observations.size() - labeled_frames},
      {"ambiguous_pixels", ambiguous},          {"labeled_pixels", labeled_pixels},
      {"depth_pixels", depth_pixels},           {"classes", classes},
      {"instances", checks.instances},          {"boxes", checks.boxes}};
  if (!checks.warnings.empty()) summary["warnings"] = checks.warnings;
  return summary;
}

}  // namespace

StageKind propagate_kind() {
  StageKind kind = make_stage_kind(
      {"propagate", params(), {"source", "calibrate", "poses", "annotations"}, {}, nullptr}, 6, nullptr, nullptr);
  kind.units = [](const StageContext& ctx) { return std::make_unique<PropagateWork>(ctx); };
  kind.unit_words = {"frame", "label", "labeled", "boxes", "box", "seeing"};
  kind.unit_names = [](const StageInput& source) {
    std::vector<std::string> units;
    const auto recording = shared_recording(source);  // held: a range-for over a temporary's member dangles
    for (const auto& o : recording->observations) units.push_back(o.sensor + "/" + o.id);
    return units;
  };
  return kind;
}

}  // namespace olt
