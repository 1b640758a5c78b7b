// `reconstruct`: every k-th observation with a valid pose, back-projected and voxel-fused into one
// coloured cloud in the world frame (binary PLY and PCD), with a preview image.
#include "olt/core/error.h"
#include "olt/core/image.h"
#include "olt/formats/cloud_files.h"
#include "olt/reconstruct/fusion.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"

namespace olt {
namespace {

struct ReconstructConfig {
  int every = 5;               ///< fuse every k-th observation
  double voxel_size_m = 0.01;  ///< edge of a fusion voxel, metres
  int pixel_stride = 2;        ///< use every n-th pixel in each direction
  int preview_size_px = 600;   ///< height of the preview image, pixels
};

std::shared_ptr<const Params<ReconstructConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<ReconstructConfig>>();
    t->integer("every", &ReconstructConfig::every, between(1, 1000000), "fuse every k-th observation")
        .number("voxel_size_m", &ReconstructConfig::voxel_size_m, between(0.001, 10), "fusion voxel edge, metres")
        .integer("pixel_stride", &ReconstructConfig::pixel_stride, between(1, 64), "use every n-th pixel per direction")
        .integer("preview_size_px", &ReconstructConfig::preview_size_px, between(64, 4096), "preview height, pixels");
    return t;
  }();
  return p;
}

nlohmann::json run(const StageContext& ctx, ArtifactWriter& out) {
  const ReconstructConfig c = params()->from_json(ctx.stage.params);
  const Recording recording = load_recording(ctx.need("source"));
  const Calibration calibration = load_calibration(ctx.need("calibrate"));
  const auto poses = load_poses(ctx.need("poses"));
  check_poses_match(recording, poses, ctx.stage.id);
  std::map<std::string, std::vector<Eigen::Vector2f>> rays;
  for (const auto& [sensor, cal] : calibration) rays[sensor] = pixel_rays(cal.depth);

  VoxelFusion fusion(c.voxel_size_m);
  int fused = 0;
  for (size_t i = 0; i < recording.observations.size(); i += static_cast<size_t>(c.every)) {
    const Observation& o = recording.observations[i];
    if (!poses.at(i).valid) continue;
    const SensorCalibration& cal = calibration.at(o.sensor);
    const cv::Mat depth = read_png_u16(o.depth.path);
    if (depth.cols != cal.depth.width || depth.rows != cal.depth.height)
      throw InputError(o.depth.path, "depth image is " + std::to_string(depth.cols) + "x" + std::to_string(depth.rows) +
                                         ", the calibration says " + std::to_string(cal.depth.width) + "x" +
                                         std::to_string(cal.depth.height));
    const cv::Mat color = o.color ? read_png_bgr(o.color->path) : cv::Mat();
    fuse_observation(fusion, depth, color, cal, rays.at(o.sensor), poses[i].T_world_sensor, c.pixel_stride);
    ++fused;
  }
  const ColoredCloud cloud = fusion.cloud();
  write_ply(out.path("scene.ply"), cloud);
  write_pcd(out.path("scene.pcd"), cloud);
  out.write("scene_preview.png", encode_png(render_preview(cloud, c.preview_size_px)));
  out.publish("scene.ply", ctx.stage.id + "/scene.ply", "scene_ply");
  out.publish("scene.pcd", ctx.stage.id + "/scene.pcd", "scene_pcd");
  out.publish("scene_preview.png", ctx.stage.id + "/scene_preview.png", "scene_preview");
  return {{"observations_fused", fused}, {"points", cloud.size()}};
}

}  // namespace

StageKind reconstruct_kind() {
  return make_stage_kind({"reconstruct", params(), {"source", "calibrate", "poses"}, {}, nullptr}, 1, nullptr, run);
}

}  // namespace olt
