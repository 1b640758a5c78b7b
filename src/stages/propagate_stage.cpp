// `propagate`: per observation with a valid pose, class and instance images (16-bit PNG, depth
// resolution) and an overlay for people; the label map (labels.json) for the whole dataset.
#include <exception>
#include <mutex>

#include "olt/core/error.h"
#include "olt/core/image.h"
#include "olt/propagate/propagate.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"

namespace olt {
namespace {

struct PropagateConfig {
  std::map<std::string, int> class_ids;  ///< fixed class ids by name (1..65534); others follow alphabetically
  bool overlays = true;                  ///< write an overlay PNG per observation
  bool keep_flagged = false;             ///< also label observations whose pose is flagged
};

std::shared_ptr<const Params<PropagateConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<PropagateConfig>>();
    t->int_map("class_ids", &PropagateConfig::class_ids, between(1, 65534), "fixed class ids by class name")
        .boolean("overlays", &PropagateConfig::overlays, "write an overlay PNG per observation")
        .boolean("keep_flagged", &PropagateConfig::keep_flagged, "also label observations with a flagged pose");
    return t;
  }();
  return p;
}

struct FrameResult {
  bool labeled = false;
  FrameLabels labels;
};

void run(StageRun& run) {
  const PropagateConfig c = params()->from_json(run.stage.params);
  const Recording recording = load_recording(*run.input("source"));
  const Calibration calibration = load_calibration(*run.input("calibrate"));
  const auto poses = load_poses(*run.input("poses"));
  check_poses_match(recording, poses, run.stage.id);
  const std::vector<Box> boxes = load_boxes(*run.input("annotations"));
  const LabelMap map = make_label_map(boxes, c.class_ids);
  const std::vector<LabeledBox> ordered = prioritized_boxes(boxes, map);
  std::map<std::string, std::vector<Eigen::Vector2f>> rays;
  for (const auto& [sensor, cal] : calibration) rays[sensor] = pixel_rays(cal.depth);

  const auto& observations = recording.observations;
  std::vector<FrameResult> results(observations.size());
  for (const auto& s : recording.sensors)
    for (const char* folder : {"class", "instance", "overlay"}) fs::create_directories(run.dir / s.id / folder);
  std::exception_ptr failure;
  std::mutex failure_mutex;
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t i = 0; i < observations.size(); ++i) {
    try {
      const Observation& o = observations[i];
      const ObservationPose& pose = poses.at(i);
      if (!pose.valid && !c.keep_flagged) continue;
      const SensorCalibration& cal = calibration.at(o.sensor);
      const cv::Mat depth = read_png_u16(o.depth.path);
      if (depth.cols != cal.depth.width || depth.rows != cal.depth.height)
        throw InputError(o.depth.path, "depth image is " + std::to_string(depth.cols) + "x" +
                                           std::to_string(depth.rows) + ", the calibration says " +
                                           std::to_string(cal.depth.width) + "x" + std::to_string(cal.depth.height));
      FrameLabels labels = label_depth_image(depth, cal, rays.at(o.sensor), pose.T_world_sensor, ordered);
      const std::string stem = o.sensor + "/";
      run.write(stem + "class/" + o.id + ".png", encode_png(labels.class_ids));
      run.write(stem + "instance/" + o.id + ".png", encode_png(labels.instance_ids));
      if (c.overlays) {
        const cv::Mat color = o.color ? read_png_bgr(o.color->path) : cv::Mat();
        run.write(stem + "overlay/" + o.id + ".png",
                  encode_png(render_overlay(color, depth, labels, map, ordered, cal, pose.T_world_sensor)));
      }
      results[i] = {true, std::move(labels)};
    } catch (...) {
      std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);

  std::map<std::string, std::pair<int64_t, int64_t>> per_class;  // name -> (pixels, frames)
  int labeled_frames = 0;
  int64_t ambiguous = 0;
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    if (!results[i].labeled) continue;
    ++labeled_frames;
    ambiguous += results[i].labels.ambiguous_pixels;
    std::map<std::string, int64_t> seen;
    for (size_t k = 0; k < ordered.size(); ++k) seen[ordered[k].box.label] += results[i].labels.box_pixels[k];
    for (const auto& [name, pixels] : seen) {
      per_class[name].first += pixels;
      per_class[name].second += pixels > 0;
    }
    const std::string stem = o.sensor + "/", out = run.stage.id + "/" + stem;
    run.publish(stem + "class/" + o.id + ".png", out + "class/" + o.id + ".png", "class_label", o.sensor, o.id,
                o.timestamp);
    run.publish(stem + "instance/" + o.id + ".png", out + "instance/" + o.id + ".png", "instance_label", o.sensor, o.id,
                o.timestamp);
    if (c.overlays)
      run.publish(stem + "overlay/" + o.id + ".png", out + "overlay/" + o.id + ".png", "overlay", o.sensor, o.id,
                  o.timestamp);
  }
  run.write("labels.json", to_json(map).dump(1) + "\n");
  run.publish("labels.json", "labels.json", "label_map");
  nlohmann::json classes = nlohmann::json::object();
  for (const auto& [name, counts] : per_class) classes[name] = {{"pixels", counts.first}, {"frames", counts.second}};
  run.summary = {{"observations_labeled", labeled_frames},
                 {"observations_skipped", observations.size() - labeled_frames},
                 {"ambiguous_pixels", ambiguous},
                 {"classes", classes}};
}

}  // namespace

StageKind propagate_kind() {
  return {{"propagate", params(), {"source", "calibrate", "poses", "annotations"}, {}, nullptr},
          1,
          [](const StageDecl&) { return std::vector<fs::path>{}; },
          run};
}

}  // namespace olt
