// Propagation benchmark on a TUM RGB-D folder with a box file: per frame, the time to read the
// depth PNG, label it, and encode the class and instance PNGs, on one core (medians), then the
// frames per second of the same work on every core; then, on the frames that see one box, that box
// moved: labeling afresh against relabeling from the previous labels. Prints one JSON line. With --exchange FILE it
// also writes the frames, poses and boxes for the peers (tests/bench/propagation_*_peer.*) and the
// number of depth points inside each box (each box alone, no overlap rule) on the first frames,
// which the peers must reproduce.
//   olt_bench_propagation DATASET_DIR BOXES_JSON [--boxes N] [--exchange FILE] [--check-frames K]
// Camera: TUM fr1 intrinsics as a plain pinhole (the peers have no distortion model), depth 0.4-5 m
// as in jobs/tum_fr1_rpy.yaml, poses from the ground truth.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "olt/core/allocator.h"
#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/core/image_strips.h"
#include "olt/core/parallel.h"
#include "olt/core/threads.h"
#include "olt/formats/annotations.h"
#include "olt/formats/tum.h"
#include "olt/model/trajectory.h"
#include "olt/propagate/propagate.h"

using namespace olt;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The job's boxes, then copies of them moved 0.35 m along x (labelled "copy") until there are n.
// The same images and counts, every box's too.
bool same_labels(const FrameLabels& a, const FrameLabels& b) {
  bool same = cv::countNonZero(a.class_ids != b.class_ids) == 0 &&
              cv::countNonZero(a.instance_ids != b.instance_ids) == 0 && a.valid_pixels == b.valid_pixels &&
              a.labeled_pixels == b.labeled_pixels && a.ambiguous_pixels == b.ambiguous_pixels &&
              a.boxes.size() == b.boxes.size();
  for (size_t k = 0; same && k < a.boxes.size(); ++k)
    same = a.boxes[k].labeled_pixels == b.boxes[k].labeled_pixels &&
           a.boxes[k].covered_pixels == b.boxes[k].covered_pixels &&
           a.boxes[k].bottom_pixels == b.boxes[k].bottom_pixels && a.boxes[k].bbox == b.boxes[k].bbox;
  return same;
}

std::vector<Box> boxes_for_bench(std::vector<Box> boxes, size_t n) {
  const size_t original = boxes.size();
  for (size_t i = 0; boxes.size() < n; ++i) {
    Box b = boxes[i % original];
    b.id += "_copy" + std::to_string(i);
    b.instance = b.id;
    b.label = "copy";
    b.T_world_box.translation().x() += 0.35 * (1 + i / original);
    boxes.push_back(b);
  }
  boxes.resize(std::min(boxes.size(), n));
  return boxes;
}

nlohmann::json matrix_json(const Eigen::Matrix4d& m) {
  nlohmann::json out = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.push_back(m(r, c));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s DATASET_DIR BOXES_JSON [--boxes N] [--exchange FILE] [--check-frames K]\n",
                 argv[0]);
    return 2;
  }
  keep_freed_memory();  // as olt does
  try {
    const fs::path dir = argv[1];
    size_t box_count = 30, check_frames = 3;
    std::string exchange;
    for (int i = 3; i + 1 < argc; i += 2) {
      const std::string flag = argv[i], value = argv[i + 1];
      if (flag == "--boxes")
        box_count = std::stoul(value);
      else if (flag == "--exchange")
        exchange = value;
      else if (flag == "--check-frames")
        check_frames = std::stoul(value);
      else
        throw std::invalid_argument("unknown option " + flag);
    }
    SensorCalibration cal;
    cal.depth = {640, 480, 517.3, 516.5, 318.6, 255.3, {}};
    cal.color = cal.depth;
    cal.depth_scale = 5000;
    cal.min_depth_m = 0.4;
    cal.max_depth_m = 5.0;
    const DepthView view = make_depth_view(cal.depth);
    const auto list = parse_tum_list((dir / "depth.txt").string(), read_file(dir / "depth.txt"));
    const Trajectory truth =
        parse_tum_trajectory((dir / "groundtruth.txt").string(), read_file(dir / "groundtruth.txt"));
    const std::vector<Box> boxes = boxes_for_bench(parse_native_annotations(argv[2], read_file(argv[2])), box_count);
    const LabelMap map = make_label_map(boxes, {});
    const auto ordered = prioritized_boxes(boxes, map);
    std::vector<Pose> poses;
    for (const auto& e : list) {
      Pose T;
      double gap;
      if (!interpolate_trajectory(truth, e.timestamp, &T, &gap))
        throw InputError(e.file, "no ground truth at this depth image's time");
      poses.push_back(T);
    }

    // One core, stage by stage.
    std::vector<double> read_ms, label_ms, write_ms, total_ms;
    int64_t labeled = 0;
    for (size_t i = 0; i < list.size(); ++i) {
      const auto start = std::chrono::steady_clock::now();
      const cv::Mat depth = read_grey16(dir / list[i].file);
      read_ms.push_back(ms_since(start));
      const auto label_start = std::chrono::steady_clock::now();
      const FrameLabels labels = label_depth_image(depth, cal, view, poses[i], ordered);
      label_ms.push_back(ms_since(label_start));
      const auto write_start = std::chrono::steady_clock::now();
      encode_label_png(labels.class_ids);
      encode_label_png(labels.instance_ids);
      write_ms.push_back(ms_since(write_start));
      total_ms.push_back(ms_since(start));
      labeled += labels.labeled_pixels;
    }

    // A one-box edit (the box b11, or the first, raised 1 cm), on the frames that see the box: label
    // afresh, against relabeling in place from the previous labels (as `olt watch` does with the
    // labels it kept; `olt run` would have to decode the previous class and instance PNGs: timed
    // too). Both give the same images and counts (checked).
    std::vector<Box> edited_boxes = boxes;
    auto moved = std::find_if(edited_boxes.begin(), edited_boxes.end(), [](const Box& b) { return b.id == "b11"; });
    if (moved == edited_boxes.end()) moved = edited_boxes.begin();
    moved->T_world_box.translation().z() += 0.01;
    const auto edited = prioritized_boxes(edited_boxes, map);
    const size_t moved_at = static_cast<size_t>(
        std::find_if(edited.begin(), edited.end(), [&](const LabeledBox& b) { return b.box.id == moved->id; }) -
        edited.begin());
    std::vector<double> afresh_ms, relabel_ms, decode_ms;
    int in_place_frames = 0;
    for (size_t i = 0; i < list.size(); ++i) {
      const auto in_view = boxes_in_view(edited, cal, view, poses[i]);
      if (std::find(in_view.begin(), in_view.end(), moved_at) == in_view.end()) continue;
      const cv::Mat depth = read_grey16(dir / list[i].file);
      const FrameLabels before = label_depth_image(depth, cal, view, poses[i], ordered);
      const std::string class_png = encode_label_png(before.class_ids),
                        instance_png = encode_label_png(before.instance_ids);
      const auto decode_start = std::chrono::steady_clock::now();
      decode_grey16(class_png, "class.png");
      decode_grey16(instance_png, "instance.png");
      decode_ms.push_back(ms_since(decode_start));
      const auto afresh_start = std::chrono::steady_clock::now();
      const FrameLabels afresh = label_depth_image(depth, cal, view, poses[i], edited);
      afresh_ms.push_back(ms_since(afresh_start));
      const auto relabel_start = std::chrono::steady_clock::now();
      const auto in_place = relabel_depth_image(depth, cal, view, poses[i], edited, ordered, before);
      const FrameLabels relabeled = in_place ? *in_place : label_depth_image(depth, cal, view, poses[i], edited);
      relabel_ms.push_back(ms_since(relabel_start));
      in_place_frames += in_place.has_value();
      if (!same_labels(afresh, relabeled))
        throw std::runtime_error("relabeling frame " + list[i].file + " differs from labeling it afresh");
    }

    // Every core, frames in parallel: wall time for all frames.
    const auto wall_start = std::chrono::steady_clock::now();
    olt::parallel_for(list.size(), [&](size_t i) {
      const cv::Mat depth = read_grey16(dir / list[i].file);
      const FrameLabels labels = label_depth_image(depth, cal, view, poses[i], ordered);
      encode_label_png(labels.class_ids);
      encode_label_png(labels.instance_ids);
    });
    const double wall_ms = ms_since(wall_start);

    nlohmann::json out = {{"name", "olt"},
                          {"frames", list.size()},
                          {"boxes", boxes.size()},
                          {"median_read_ms", median(read_ms)},
                          {"median_label_ms", median(label_ms)},
                          {"median_write_ms", median(write_ms)},
                          {"median_total_ms", median(total_ms)},
                          {"fps_one_core", 1000.0 / median(total_ms)},
                          {"cores", olt::usable_threads().threads},
                          {"fps_all_cores", 1000.0 * list.size() / wall_ms},
                          {"labeled_pixels", labeled},
                          {"one_box_edit",
                           {{"box", moved->id},
                            {"frames_seeing", afresh_ms.size()},
                            {"frames_in_place", in_place_frames},
                            {"median_label_afresh_ms", median(afresh_ms)},
                            {"median_relabel_ms", median(relabel_ms)},
                            {"median_decode_previous_ms", median(decode_ms)}}}};

    if (!exchange.empty()) {
      nlohmann::json frames = nlohmann::json::array(), box_list = nlohmann::json::array(),
                     inside = nlohmann::json::array();
      for (size_t i = 0; i < list.size(); ++i)
        frames.push_back({{"id", list[i].stamp_text},
                          {"depth", fs::absolute(dir / list[i].file).string()},
                          {"T_world_sensor", matrix_json(poses[i].matrix())}});
      for (const auto& lb : ordered) {
        const Eigen::Matrix3d R = lb.box.T_world_box.linear();
        const Eigen::Vector3d t = lb.box.T_world_box.translation();
        box_list.push_back(
            {{"id", lb.box.id},
             {"center", {t.x(), t.y(), t.z()}},
             {"rotation", {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)}},
             {"size", {lb.box.size.x(), lb.box.size.y(), lb.box.size.z()}}});
      }
      // Points inside each box on its own, for the peers to agree with.
      for (size_t i = 0; i < std::min(check_frames, list.size()); ++i) {
        const cv::Mat depth = read_grey16(dir / list[i].file);
        nlohmann::json counts = nlohmann::json::array();
        for (const auto& lb : ordered)
          counts.push_back(label_depth_image(depth, cal, view, poses[i], {lb}).labeled_pixels);
        inside.push_back(counts);
      }
      const nlohmann::json j = {{"intrinsics",
                                 {{"width", cal.depth.width},
                                  {"height", cal.depth.height},
                                  {"fx", cal.depth.fx},
                                  {"fy", cal.depth.fy},
                                  {"cx", cal.depth.cx},
                                  {"cy", cal.depth.cy}}},
                                {"depth_scale", cal.depth_scale},
                                {"min_depth_m", cal.min_depth_m},
                                {"max_depth_m", cal.max_depth_m},
                                {"frames", frames},
                                {"boxes", box_list}};
      write_file_atomic(exchange, j.dump());
      out["inside"] = inside;
    }
    std::printf("%s\n", out.dump().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
