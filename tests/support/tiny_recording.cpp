#include "support/tiny_recording.h"

#include <catch2/catch.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "olt/core/image.h"
#include "olt/core/image_codec.h"
#include "support/temp_dir.h"

namespace olt::test {

const char* const kTinyTumJob = R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: tum, path: data}}
  calibrate: {kind: calibrate, needs: [source], params: {sensors: {rgbd: {depth_intrinsics: [50, 50, 32, 24], depth_scale: 5000}}}}
  poses: {kind: poses, needs: [calibrate], params: {trajectory: data/groundtruth.txt}}
  scene: {kind: reconstruct, needs: [poses]}
  annotations: {kind: annotations, params: {file: boxes.json, frame: world}}
  labels: {kind: propagate, needs: [poses, annotations]}
)";

const char* const kTinyTumBoxes =
    R"({"version": 1, "boxes": [{"id": "b1", "label": "thing", "center": [0, 0, 1], "size": [0.5, 0.5, 0.5], "rotation": [0, 0, 0, 1]}]})";

void write_tiny_tum_recording(const std::filesystem::path& dir, const std::string& color_extension) {
  std::string depth_list, rgb_list, truth;
  for (int i = 0; i < 3; ++i) {
    write_text(dir / ("depth/" + std::to_string(i) + ".png"),
               olt::encode_png(cv::Mat(48, 64, CV_16UC1, cv::Scalar(5000 + 100 * i))));
    std::vector<unsigned char> color;
    REQUIRE(olt::image_codec().encode(cv::Mat(48, 64, CV_8UC3, cv::Scalar(90, 100, 110)), color_extension, {}, color));
    write_text(dir / ("rgb/" + std::to_string(i) + color_extension), std::string(color.begin(), color.end()));
    depth_list += std::to_string(1.0 + 0.1 * i) + " depth/" + std::to_string(i) + ".png\n";
    rgb_list += std::to_string(1.0 + 0.1 * i) + " rgb/" + std::to_string(i) + color_extension + "\n";
  }
  for (int i = 0; i < 40; ++i)
    truth += std::to_string(0.95 + 0.01 * i) + " 0 0 " + std::to_string(0.001 * i) + " 0 0 0 1\n";
  write_text(dir / "depth.txt", "# timestamp filename\n" + depth_list);
  write_text(dir / "rgb.txt", rgb_list);
  write_text(dir / "groundtruth.txt", truth);
}

std::string run_tiny_tum_job(const std::filesystem::path& root, const std::string& job, const std::string& boxes,
                             const std::string& color_extension) {
  write_tiny_tum_recording(root / "data", color_extension);
  write_text(root / "job.yaml", job);
  write_text(root / "boxes.json", boxes);
  const auto run = run_olt("run " + (root / "job.yaml").string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  return run.err;
}

}  // namespace olt::test
