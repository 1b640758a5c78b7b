// The OLT / Robot@Home plain-text layout end to end: the synthetic robot written in that layout
// (sequence file, <id>_scan.txt, <id>_depth.png at 65535/10 units per metre, <id>_intensity.png),
// read back, mapped by laser, posed and labeled; judged against the exact truth.
#include "olt/formats/plain_text_layout.h"

#include <catch2/catch.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "olt/core/image.h"
#include "support/synthetic_truth.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

// MRPT ticks: 100 ns since 1601-01-01.
std::string ticks(double unix_seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%lld", static_cast<long long>(std::llround((unix_seconds + 11644473600.0) * 1e7)));
  return text;
}

std::string pose_text(const Pose& T) {               // x y z yaw pitch roll (radians), R = Rz Ry Rx
  const Eigen::Vector3d a = angles_zyx(T.linear());  // (rx, ry, rz)
  char text[160];
  std::snprintf(text, sizeof(text), "%.9f %.9f %.9f %.9f %.9f %.9f", T.translation().x(), T.translation().y(),
                T.translation().z(), a.z(), a.y(), a.x());
  return text;
}

void write_layout(const SyntheticScene& scene, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir / "seq");
  std::string sequence = "# [Observation_id] [sensor_label] [x y z yaw pitch roll] [time-stamp]\n";
  size_t scan = 0, shot = 0, id = 0;
  while (scan < scene.scans.size() || shot < scene.timestamps.size()) {
    const bool take_scan = shot == scene.timestamps.size() ||
                           (scan < scene.scans.size() && scene.scans[scan].timestamp < scene.timestamps[shot]);
    const std::string name = std::to_string(id++);
    if (take_scan) {
      const LaserScan& s = scene.scans[scan++];
      sequence += name + " HOKUYO1 " + pose_text(s.T_robot_laser) + " " + ticks(s.timestamp) + "\n";
      std::string text = "# a 2D laser scan\n# [aperture] [max_range] [number_of_scans]\n";
      text += std::to_string(s.aperture_rad) + "\n" + std::to_string(s.max_range_m) + "\n" +
              std::to_string(s.ranges.size()) + "\n";
      for (float r : s.ranges) text += std::to_string(r) + " ";
      text += "\n";
      for (uint8_t v : s.valid) text += v ? "1 " : "0 ";
      write_text(dir / "seq" / (name + "_scan.txt"), text + "\n");
    } else {
      const size_t i = shot++;
      const int camera = scene.camera_of[i];
      const Pose mrpt_pose = scene.T_robot_camera[camera] * mrpt_camera_from_optical().inverse();
      sequence +=
          name + " " + scene.sensors[camera] + " " + pose_text(mrpt_pose) + " " + ticks(scene.timestamps[i]) + "\n";
      const SyntheticFrame frame = render_synthetic_frame(scene, i);
      cv::Mat depth;
      frame.depth.convertTo(depth, CV_16UC1, kPlainTextDepthScale / scene.config.depth_scale);
      write_text(dir / "seq" / (name + "_depth.png"), encode_png(depth));
      write_text(dir / "seq" / (name + "_intensity.png"), encode_png(frame.color));
    }
  }
  write_text(dir / "seq.txt", sequence);
}

}  // namespace

TEST_CASE("plain-text layout: the synthetic robot read back, laser-posed and labeled >= 98% exactly") {
  SyntheticConfig config;
  config.cameras = 2;
  config.frames = 12;
  config.rate_hz = 2.5;
  config.width = 160;
  config.height = 120;
  const SyntheticScene scene = make_synthetic_scene(config);
  TempDir dir;
  write_layout(scene, dir.path());
  // The layout has no intrinsics (the job gives them) and no odometry. The map's frame is the robot
  // at the first scan: the boxes are drawn in it, as an annotator of the scene would.
  Pose T_world_map;
  double gap;
  REQUIRE(interpolate_trajectory(scene.robot_truth, scene.scans.front().timestamp, &T_world_map, &gap));
  const Intrinsics& k = scene.camera;
  char calibration[512];
  std::snprintf(calibration, sizeof(calibration), "{depth_intrinsics: [%.6f, %.6f, %.6f, %.6f], max_depth_m: 8}", k.fx,
                k.fy, k.cx, k.cy);
  write_text(dir / "job.yaml", std::string(R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: plain_text, path: seq.txt}}
  calibrate: {kind: calibrate, needs: [source], params: {sensors: {RGBD_1: )") +
                                   calibration + ", RGBD_2: " + calibration + R"(}}}
  laser_map: {kind: laser_map, needs: [source]}
  map_poses: {kind: poses, needs: [calibrate, laser_map], params: {method: laser}}
  annotations: {kind: annotations, params: {file: boxes.json}}
  labels: {kind: propagate, needs: [map_poses, annotations], params: {overlays: false, color_labels: false}}
)");
  write_text(dir / "boxes.json", [&] {
    nlohmann::json boxes = nlohmann::json::array();
    for (const Box& b : scene.annotations) {
      const Pose T_map_box = T_world_map.inverse() * b.T_world_box;
      const Eigen::Quaterniond q(T_map_box.linear());
      const Eigen::Vector3d c = T_map_box.translation();
      boxes.push_back({{"id", b.id},
                       {"label", b.label},
                       {"instance", b.instance},
                       {"center", {c.x(), c.y(), c.z()}},
                       {"size", {b.size.x(), b.size.y(), b.size.z()}},
                       {"rotation", {q.x(), q.y(), q.z(), q.w()}}});
    }
    return nlohmann::json{{"version", 1}, {"boxes", boxes}}.dump();
  }());
  const Completed run = run_olt("run " + (dir / "job.yaml").string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto calibration_json = nlohmann::json::parse(read_text(dir / "out/calibrate/calibration.json"));
  CHECK(calibration_json["RGBD_1"]["depth_scale"].get<double>() == Approx(kPlainTextDepthScale));
  const SyntheticJudgement j = judge_synthetic_run(dir / "out", "map_poses", config, T_world_map);
  CHECK(j.observations == 24);
  CHECK(j.translation_max_m < 0.02);
  CHECK(j.rotation_max_deg < 0.3);
  CHECK(j.label_agreement >= 0.98);
}
