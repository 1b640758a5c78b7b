// `reconstruct` (olt/stages/reconstruct.h): the function, and its codec — the recording, calibration
// and poses in; scene.ply, scene.pcd (binary), scene_preview.png (in the annotation frame) and
// annotation_frame.json out; scene_points.bin (olt/formats/scene_points.h) kept, not published, for
// the report to draw the scene with its boxes.
#include <cmath>

#include "olt/core/error.h"
#include "olt/core/image.h"
#include "olt/core/progress.h"
#include "olt/formats/cloud_files.h"
#include "olt/formats/scene_points.h"
#include "olt/reconstruct/fusion.h"
#include "olt/reconstruct/preview.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
#include "olt/stages/reconstruct.h"
#include "olt/stages/typed_stage.h"

namespace olt {

ReconstructResult run_reconstruct(const ReconstructInputs& in, const ReconstructConfig& c) {
  std::map<std::string, std::vector<Eigen::Vector2f>> rays;
  for (const auto& [sensor, cal] : in.calibration) rays[sensor] = pixel_rays(cal.depth);
  VoxelFusion fusion(c.voxel_size_m);
  ReconstructResult result;
  result.voxel_size_m = c.voxel_size_m;
  const size_t every = static_cast<size_t>(c.every);
  Progress progress("observations fused", (in.recording->observations.size() + every - 1) / every);
  for (size_t i = 0; i < in.recording->observations.size(); i += every) {
    progress.advance();
    const Observation& o = in.recording->observations[i];
    if (!in.poses->at(i).valid) continue;
    const SensorCalibration& cal = in.calibration.at(o.sensor);
    const cv::Mat depth = read_grey16(o.depth.file());
    if (depth.cols != cal.depth.width || depth.rows != cal.depth.height)
      throw InputError(o.depth.file(), "depth image is " + std::to_string(depth.cols) + "x" +
                                           std::to_string(depth.rows) + ", the calibration says " +
                                           std::to_string(cal.depth.width) + "x" + std::to_string(cal.depth.height));
    const cv::Mat color = o.color ? read_color(o.color->file()) : cv::Mat();
    fuse_observation(fusion, depth, color, cal, rays.at(o.sensor), (*in.poses)[i].T_world_sensor, c.pixel_stride);
    ++result.observations_fused;
  }
  result.cloud = fusion.cloud();
  std::vector<Pose> cameras;
  for (size_t i = 0; i < in.recording->observations.size(); i += static_cast<size_t>(c.every))
    if (in.poses->at(i).valid) cameras.push_back((*in.poses)[i].T_world_sensor);
  LevelConfig level{c.level, std::nullopt, c.voxel_size_m};
  if (c.up.size() == 3) level.up = Eigen::Vector3d(c.up[0], c.up[1], c.up[2]);
  result.frame = find_annotation_frame(result.cloud, cameras, level);
  const Eigen::Isometry3f T_annotation_world = result.frame.T_world_annotation.inverse().cast<float>();
  for (auto& p : result.cloud) {
    const Eigen::Vector3f q = T_annotation_world * Eigen::Vector3f(p.x, p.y, p.z);
    p.x = q.x(), p.y = q.y(), p.z = q.z();
  }
  const PreviewLayout layout = preview_layout(scene_region(result.cloud, kScenePicturePadM), c.preview_size_px);
  result.preview = render_preview(result.cloud, layout, {c.voxel_size_m, true, ""});
  return result;
}

namespace {

std::shared_ptr<const Params<ReconstructConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<ReconstructConfig>>();
    t->integer("every", &ReconstructConfig::every, between(1, 1000000), "fuse every k-th observation")
        .number("voxel_size_m", &ReconstructConfig::voxel_size_m, between(0.001, 10), "fusion voxel edge, metres")
        .integer("pixel_stride", &ReconstructConfig::pixel_stride, between(1, 64), "use every n-th pixel per direction")
        .integer("preview_size_px", &ReconstructConfig::preview_size_px, between(64, 4096), "preview height, pixels")
        .boolean("level", &ReconstructConfig::level,
                 "publish the scene levelled (z up, origin on the floor); false: in the poses' frame")
        .numbers("up", &ReconstructConfig::up, 3, "up in the poses' frame, given instead of found from the floor");
    return t;
  }();
  return p;
}

ReconstructInputs load(const StageContext& context) {
  ReconstructInputs in{shared_recording(context.need("source")), load_calibration(context.need("calibrate")),
                       shared_poses(context.need("poses"))};
  check_poses_match(*in.recording, *in.poses, context.stage.id);
  return in;
}

nlohmann::json save(const ReconstructResult& result, const StageContext& context, ArtifactWriter& out) {
  write_ply(out.path("scene.ply"), result.cloud);
  write_pcd(out.path("scene.pcd"), result.cloud);
  out.write("scene_points.bin", encode_scene_points({result.cloud, static_cast<float>(result.voxel_size_m)}));
  out.write("scene_preview.png", encode_png(result.preview));
  out.write("annotation_frame.json", to_json(result.frame).dump(1) + "\n");
  for (const auto& [file, kind] : {std::pair{"scene.ply", "scene_ply"},
                                   {"scene.pcd", "scene_pcd"},
                                   {"scene_preview.png", "scene_preview"},
                                   {"annotation_frame.json", "annotation_frame"}})
    out.publish(file, context.stage.id + "/" + file, kind);
  return {{"observations_fused", result.observations_fused},
          {"points", result.cloud.size()},
          {"levelled_by", result.frame.method},
          {"tilt_deg", std::round(result.frame.tilt_deg() * 10) / 10}};
}

}  // namespace

StageKind reconstruct_kind() {
  // 3: the preview has a grid, axes and a scale bar; scene_points.bin for the report
  StageKind kind = make_stage_kind({"reconstruct", params(), {"source", "calibrate", "poses"}, {}, nullptr}, 3, nullptr,
                                   typed_stage(params(), load, run_reconstruct, save));
  kind.looks_up = {{"source", recording_lookup}};  // the recording, its images by name
  return kind;
}

}  // namespace olt
