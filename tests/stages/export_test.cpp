// The export stage on the synthetic recording: COCO masks decode to exactly the propagated instance
// pixels, and the per-observation sensor-frame boxes map back to the scene boxes.
#include "olt/stages/export.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "olt/core/image.h"
#include "olt/formats/annotations.h"
#include "olt/formats/coco.h"
#include "olt/formats/tum.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;
using nlohmann::json;

TEST_CASE("export: COCO masks equal the instance images - sensor boxes equal the scene boxes") {
  TempDir dir;
  write_text(dir / "job.yaml", R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: 4, width: 160, height: 120}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations], params: {overlays: false}}
  dataset: {kind: export, needs: [labels]}
)");
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  const json coco = json::parse(read_text(dir / "out/dataset/instances.json"));
  REQUIRE(coco["images"].size() == 4);
  REQUIRE(coco["annotations"].size() >= 4);
  const json labels = json::parse(read_text(dir / "out/labels.json"));
  CHECK(coco["categories"].size() == labels["classes"].size());

  std::map<int, cv::Mat> instance_images;
  for (const auto& image : coco["images"]) {
    const std::string id = image["olt_observation"];
    instance_images[image["id"]] = read_grey16(dir / ("out/labels/rgbd/instance/" + id + ".png"));
  }
  std::map<std::string, int> instance_id;
  for (const auto& i : labels["instances"]) instance_id[i["name"]] = i["id"];
  for (const auto& a : coco["annotations"]) {
    const cv::Mat& instances = instance_images.at(a["image_id"]);
    const auto runs = decode_coco_rle(a["segmentation"]["counts"]);
    // expand the column-major runs and compare pixel by pixel
    std::vector<uint8_t> decoded;
    bool inside = false;
    for (uint32_t r : runs) {
      decoded.insert(decoded.end(), r, inside ? 1 : 0);
      inside = !inside;
    }
    REQUIRE(decoded.size() == static_cast<size_t>(instances.total()));
    const int id = instance_id.at(a["olt_instance"]);
    int mismatches = 0, area = 0;
    for (int u = 0; u < instances.cols; ++u)
      for (int v = 0; v < instances.rows; ++v) {
        const bool expected = instances.at<uint16_t>(v, u) == id;
        area += expected;
        mismatches += expected != (decoded[static_cast<size_t>(u) * instances.rows + v] == 1);
      }
    CHECK(mismatches == 0);
    CHECK(a["area"] == area);
  }

  // Sensor-frame boxes: T_world_sensor * (sensor-frame centre) is the scene centre.
  const auto boxes = parse_native_annotations("b", read_text(dir / "out/annotations/boxes.json"));
  const auto trajectory = parse_tum_trajectory("t", read_text(dir / "out/poses/trajectory_rgbd.txt"));
  const json frame = json::parse(read_text(dir / "out/dataset/rgbd/boxes/000002.json"));
  REQUIRE(!frame["boxes"].empty());
  for (const auto& b : frame["boxes"]) {
    const Eigen::Vector3d c(b["center"][0], b["center"][1], b["center"][2]);
    for (const auto& scene_box : boxes)
      if (scene_box.id == b["id"]) CHECK((trajectory[2].pose * c).isApprox(scene_box.T_world_box.translation(), 1e-6));
  }
  CHECK_THAT(read_text(dir / "out/dataset/labels.yaml"), Catch::Contains("ignore_index: 65535"));
  CHECK(coco["images"][0]["file_name"] == "rgb/000000.png");  // relative to the recording
}

TEST_CASE(
    "export: a frame's masks come through the inputs' reader - COCO entries and sensor boxes from them, in memory") {
  ExportInputs in;
  Box chair;
  chair.id = "b1";
  chair.label = "chair";
  chair.instance = "chair_1";
  chair.T_world_box.translation() = Eigen::Vector3d(0, 0, 2);  // 2 m in front of a camera at the origin
  in.boxes = {chair};
  in.map = make_label_map(in.boxes, {});
  Recording recording;
  recording.observations = {Observation{"f1", "cam", 1.5, {"/rec/depth/f1.png", Digest()}, std::nullopt, 0},
                            Observation{"f2", "cam", 2.5, {"/rec/depth/f2.png", Digest()}, std::nullopt, 0}};
  in.recording = std::make_shared<const Recording>(recording);
  ObservationPose pose;
  pose.observation = "f1", pose.sensor = "cam", pose.timestamp = 1.5, pose.valid = true;
  std::vector<ObservationPose> poses = {pose, pose};
  poses[1].observation = "f2";
  in.poses = std::make_shared<const std::vector<ObservationPose>>(poses);
  in.masks_file = [](size_t i) {  // f2 not labeled
    return i == 0 ? std::optional<MasksFile>(MasksFile{"/mem/f1/masks.json", Digest()}) : std::nullopt;
  };
  in.image_root = "/rec";
  const uint16_t chair_id = in.map.instance_id("chair_1");
  cv::Mat instances(4, 6, CV_16UC1, cv::Scalar(0));
  instances(cv::Rect(2, 1, 3, 2)).setTo(chair_id);
  std::vector<fs::path> read;
  in.read = [&](const fs::path& file) {
    read.push_back(file);
    return frame_masks_text(instances, {0, 65535});
  };
  const ExportResult result = run_export(in, ExportConfig{});
  CHECK(read == std::vector<fs::path>{"/mem/f1/masks.json"});
  std::string coco_text;
  for (const auto& part : result.coco) part.for_each_piece([&](std::string_view piece) { coco_text += piece; });
  const json coco = json::parse(coco_text);
  REQUIRE(coco["images"].size() == 1);
  CHECK(coco["images"][0]["file_name"] == "depth/f1.png");
  CHECK(coco["images"][0]["width"] == 6);
  REQUIRE(coco["annotations"].size() == 1);
  CHECK(coco["annotations"][0]["area"] == 6);
  CHECK(coco["annotations"][0]["bbox"] == json::array({2, 1, 3, 2}));
  CHECK(coco["annotations"][0]["segmentation"]["counts"] == coco_rle_string(mask_runs(instances == chair_id)));
  REQUIRE(result.sensor_boxes.size() == 1);
  const json boxes = json::parse(sensor_boxes_text(result, result.sensor_boxes[0]));
  REQUIRE(boxes["boxes"].size() == 1);
  CHECK(boxes["boxes"][0]["center"] == json::array({0.0, 0.0, 2.0}));
}
