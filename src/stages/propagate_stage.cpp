// `propagate`: per observation with a valid pose, class and instance images (16-bit PNG, depth
// resolution), a frame record (JSON: every box in view, its pixels, visible fraction and
// rectangle; the pose's quality) and an overlay for people; the label map (labels.json) for the
// whole dataset.
//
// Each frame is cached on its own, keyed by what its labels depend on: its depth (and colour)
// digest, its pose, its sensor's calibration, the parameters and only the boxes it can see. After
// an annotation edit, only frames that see the old or the new box are labeled again; the others
// are linked from the cache.
#include <algorithm>
#include <atomic>
#include <optional>

#include "olt/core/parallel.h"
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

// The stage's inputs, loaded, and per observation what its frame would be made from.
struct Prepared {
  PropagateConfig config;
  Recording recording;
  Calibration calibration;
  std::vector<ObservationPose> poses;
  LabelMap map;
  std::map<std::string, DepthView> views;
  std::vector<std::optional<FrameInputs>> frames;  ///< per observation; none when its pose is flagged
  std::vector<nlohmann::json> inputs_records;      ///< per labeled observation
};

std::unique_ptr<Prepared> prepare(const StageRun& run) {
  auto p = std::make_unique<Prepared>();
  p->config = params()->from_json(run.stage.params);
  p->recording = load_recording(*run.input("source"));
  p->calibration = load_calibration(*run.input("calibrate"));
  p->poses = load_poses(*run.input("poses"));
  check_poses_match(p->recording, p->poses, run.stage.id);
  const std::vector<Box> boxes = load_boxes(*run.input("annotations"));
  p->map = make_label_map(boxes, p->config.class_ids);
  const std::vector<LabeledBox> ordered = prioritized_boxes(boxes, p->map);
  for (const auto& [sensor, cal] : p->calibration) p->views[sensor] = make_depth_view(cal.depth);
  const auto& observations = p->recording.observations;
  p->frames.resize(observations.size());
  p->inputs_records.resize(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    const ObservationPose& pose = p->poses.at(i);
    if (!pose.valid && !p->config.keep_flagged) continue;
    FrameInputs f{o, pose, p->calibration.at(o.sensor), p->views.at(o.sensor), {}};
    for (size_t k : boxes_in_view(ordered, f.calibration, f.view, pose.T_world_sensor)) f.boxes.push_back(ordered[k]);
    p->inputs_records[i] = frame_inputs_record(f, p->config, p->map);
    p->frames[i].emplace(std::move(f));
  }
  return p;
}

// A shard's part of the work (olt run --shard): its frames labeled into the cache, nothing else.
void run_shard(StageRun& run, const Prepared& p) {
  std::atomic<int> relabeled{0}, owned{0};
  parallel_for(p.frames.size(), [&](size_t i) {
    if (!p.frames[i] || !run.share.owns(i)) return;
    const std::string key = frame_key(p.inputs_records[i]);
    const bool cached = run.parts.find(key).has_value();
    if (!cached) label_frame(*p.frames[i], key, p.config, p.map, run.parts);
    ++owned;
    relabeled += !cached;
  });
  if (relabeled > 0) run.parts.sync();
  run.report = {{"observations_relabeled", relabeled.load()}, {"observations_reused", owned - relabeled}};
}

// For `olt merge`: the frames that no shard left in the cache, as "sensor/observation (shard i/N)".
std::vector<std::string> missing_frames(const StageRun& run, const Prepared& p) {
  std::vector<std::string> missing;
  for (size_t i = 0; i < p.frames.size(); ++i)
    if (p.frames[i] && !run.parts.find(frame_key(p.inputs_records[i]))) {
      const Observation& o = p.frames[i]->observation;
      missing.push_back(o.sensor + "/" + o.id + " (shard " + std::to_string(i % run.share.count) + "/" +
                        std::to_string(run.share.count) + ")");
    }
  return missing;
}

void run(StageRun& run) {
  const auto prepared = prepare(run);
  const Prepared& p = *prepared;
  if (run.share.sharded()) return run_shard(run, p);
  if (run.share.assemble_only) {
    const auto missing = missing_frames(run, p);
    if (!missing.empty()) {
      std::string list;
      for (size_t i = 0; i < missing.size() && i < 5; ++i) list += (i ? ", " : "") + missing[i];
      throw ShardsIncomplete(std::to_string(missing.size()) + " frame(s) of stage '" + run.stage.id +
                             "' are not in the cache: " + list + (missing.size() > 5 ? ", ..." : "") +
                             "; the shards ran on other inputs, or their cache entries were removed");
    }
  }
  const PropagateConfig& c = p.config;
  const auto& observations = p.recording.observations;
  std::vector<nlohmann::json> records(observations.size());
  nlohmann::json frames_index = nlohmann::json::object();
  std::atomic<int> relabeled{0};
  parallel_for(observations.size(), [&](size_t i) {
    if (!p.frames[i]) return;
    const FrameInputs& f = *p.frames[i];
    const Observation& o = f.observation;
    const std::string key = frame_key(p.inputs_records[i]);
    std::optional<Artifact> frame = run.parts.find(key);
    if (!frame) {
      frame = label_frame(f, key, c, p.map, run.parts);
      ++relabeled;
    }
    const std::string stem = o.sensor + "/";
    run.link(stem + "class/" + o.id + ".png", *frame, "class.png");
    run.link(stem + "instance/" + o.id + ".png", *frame, "instance.png");
    run.link(stem + "frames/" + o.id + ".json", *frame, "frame.json");
    if (c.overlays) run.link(stem + "overlay/" + o.id + ".jpg", *frame, "overlay.jpg");
    if (c.point_clouds != CloudFiles::none)
      run.link(stem + "clouds/" + o.id + "." + name_of(c.point_clouds), *frame, "cloud." + name_of(c.point_clouds));
    if (c.color_labels && o.color) {
      run.link(stem + "class_color/" + o.id + ".png", *frame, "class_color.png");
      run.link(stem + "instance_color/" + o.id + ".png", *frame, "instance_color.png");
    }
    records[i] = nlohmann::json::parse(read_file(frame->dir / "frame.json"));
  });
  for (size_t i = 0; i < observations.size(); ++i)
    if (p.frames[i]) frames_index[observations[i].sensor + "/" + observations[i].id] = p.inputs_records[i];
  run.write("frames.json", frames_index.dump(1) + "\n");

  std::map<std::string, std::pair<int64_t, int64_t>> per_class;  // name -> (pixels, frames)
  int labeled_frames = 0;
  int64_t ambiguous = 0;
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    if (records[i].is_null()) continue;
    ++labeled_frames;
    ambiguous += records[i]["ambiguous_pixels"].get<int64_t>();
    std::map<std::string, int64_t> seen;
    for (const auto& b : records[i]["boxes"]) seen[b["label"]] += b["labeled_pixels"].get<int64_t>();
    for (const auto& [name, pixels] : seen) {
      per_class[name].first += pixels;
      per_class[name].second += pixels > 0;
    }
    const std::string stem = o.sensor + "/", out = run.stage.id + "/" + stem;
    auto publish = [&](const std::string& folder, const std::string& extension, const std::string& kind) {
      const std::string file = folder + "/" + o.id + extension;
      run.publish(stem + file, out + file, kind, o.sensor, o.id, o.timestamp);
    };
    publish("class", ".png", "class_label");
    publish("instance", ".png", "instance_label");
    publish("frames", ".json", "frame_labels");
    if (c.overlays) publish("overlay", ".jpg", "overlay");
    if (c.point_clouds != CloudFiles::none) publish("clouds", "." + name_of(c.point_clouds), "labeled_cloud");
    if (c.color_labels && o.color) {
      publish("class_color", ".png", "class_label_color");
      publish("instance_color", ".png", "instance_label_color");
    }
  }
  run.write("labels.json", to_json(p.map).dump(1) + "\n");
  run.publish("labels.json", "labels.json", "label_map");
  nlohmann::json classes = nlohmann::json::object();
  for (const auto& [name, counts] : per_class) classes[name] = {{"pixels", counts.first}, {"frames", counts.second}};
  run.report = {{"observations_relabeled", relabeled.load()}, {"observations_reused", labeled_frames - relabeled}};
  run.summary = {{"observations_labeled", labeled_frames},
                 {"observations_skipped", observations.size() - labeled_frames},
                 {"ambiguous_pixels", ambiguous},
                 {"classes", classes}};
}

// Why a frame is labeled again: what differs between its inputs record and the previous run's,
// as a cause ("pose changed", ...) or, when only boxes differ, the boxes it sees that changed.
std::string relabel_cause(const nlohmann::json& now, const nlohmann::json& before, std::vector<std::string>* boxes) {
  if (before.is_null()) return "not labeled in the previous run";
  for (const char* part : {"depth", "color", "pose", "calibration"})
    if (now[part] != before[part]) return std::string(part) + " changed";
  if (now["frame_version"] != before["frame_version"] || now["overlays"] != before["overlays"] ||
      now["color_labels"] != before["color_labels"] || now["point_clouds"] != before["point_clouds"])
    return "settings changed";
  for (const auto& [id, digest] : now["boxes"].items())
    if (!before["boxes"].contains(id) || before["boxes"][id] != digest) boxes->push_back(id);
  for (const auto& [id, digest] : before["boxes"].items())
    if (!now["boxes"].contains(id)) boxes->push_back(id);
  return boxes->empty() ? "not in the cache" : "";
}

// For `olt plan`: how many frames would be labeled, how many reused, and why.
nlohmann::json plan(const StageRun& run) {
  const auto p = prepare(run);
  nlohmann::json before = nlohmann::json::object();
  if (run.previous && run.previous->file("frames.json"))
    before = nlohmann::json::parse(read_file(run.previous->dir / "frames.json"));
  int to_label = 0, reused = 0;
  std::map<std::string, int> causes, boxes;  // frames per cause, frames per changed box they see
  const auto& observations = p->recording.observations;
  for (size_t i = 0; i < observations.size(); ++i) {
    if (!p->frames[i]) continue;
    if (run.parts.find(frame_key(p->inputs_records[i]))) {
      ++reused;
      continue;
    }
    ++to_label;
    const std::string id = observations[i].sensor + "/" + observations[i].id;
    std::vector<std::string> changed;
    const std::string cause =
        relabel_cause(p->inputs_records[i], before.contains(id) ? before[id] : nlohmann::json(), &changed);
    if (!cause.empty()) ++causes[cause];
    for (const auto& box : changed) ++boxes[box];
  }
  std::string text = std::to_string(to_label) + " of " + std::to_string(to_label + reused) + " frames to label";
  for (const auto& [cause, count] : causes) text += "; " + std::to_string(count) + ": " + cause;
  if (!boxes.empty()) {
    std::vector<std::pair<int, std::string>> ranked;
    for (const auto& [box, count] : boxes) ranked.emplace_back(-count, box);
    std::sort(ranked.begin(), ranked.end());
    text += "; frames seeing changed box";
    for (size_t i = 0; i < ranked.size() && i < 5; ++i)
      text += (i ? ", " : " ") + ranked[i].second + " (" + std::to_string(-ranked[i].first) + ")";
    if (ranked.size() > 5) text += " and " + std::to_string(ranked.size() - 5) + " more boxes";
  }
  return {{"frames_to_label", to_label},
          {"frames_reused", reused},
          {"causes", causes},
          {"frames_seeing_changed_box", boxes},
          {"text", text}};
}

}  // namespace

StageKind propagate_kind() {
  StageKind kind = make_stage_kind(
      {"propagate", params(), {"source", "calibrate", "poses", "annotations"}, {}, nullptr}, 3, nullptr, run);
  kind.plan = plan;
  kind.per_frame = true;
  kind.frame_units = [](const StageInput& source) {
    std::vector<std::string> units;
    for (const auto& o : load_recording(source).observations) units.push_back(o.sensor + "/" + o.id);
    return units;
  };
  return kind;
}

}  // namespace olt
