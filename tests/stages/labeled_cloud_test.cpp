// Labeled point clouds from the propagate stage: the PCD's fields, and its labels agree with the
// class and instance images point for point.
#include <catch2/catch.hpp>
#include <cstring>
#include <map>
#include <sstream>

#include "olt/core/image.h"
#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

// Two synthetic frames labeled, with a labeled cloud of `kind` each; the calibrate stage's `params`.
std::string cloud_job(const std::string& kind, const std::string& calibrate_params = "") {
  return R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: 2, width: 160, height: 120}}
  calibrate: {kind: calibrate, needs: [source])" +
         calibrate_params + R"(}
  poses: {kind: poses, needs: [calibrate]}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations], params: {point_clouds: )" +
         kind + R"(, overlays: false}}
)";
}

}  // namespace

TEST_CASE("labeled PCD per observation: fields x y z rgb class instance - labels equal the label images") {
  TempDir dir;
  write_text(dir / "job.yaml", cloud_job("pcd"));
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  const fs::path cloud_file = dir / "out/labels/rgbd/clouds/000001.pcd";
  REQUIRE(fs::exists(cloud_file));
  const std::string bytes = read_text(cloud_file);
  const size_t data = bytes.find("DATA binary\n");
  REQUIRE(data != std::string::npos);
  const std::string header = bytes.substr(0, data);
  CHECK_THAT(header, Catch::Contains("FIELDS x y z rgb class instance") && Catch::Contains("SIZE 4 4 4 4 2 2") &&
                         Catch::Contains("TYPE F F F F U U"));
  size_t points = 0;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("POINTS ", 0) == 0) points = std::stoul(line.substr(7));
  const char* body = bytes.data() + data + std::strlen("DATA binary\n");
  REQUIRE(bytes.size() - (data + std::strlen("DATA binary\n")) >= points * 20);  // PCL pads to a page

  // Class and instance counts in the cloud equal those of the images' pixels with depth.
  const cv::Mat classes = olt::read_grey16(dir / "out/labels/rgbd/class/000001.png");
  const cv::Mat instances = olt::read_grey16(dir / "out/labels/rgbd/instance/000001.png");
  std::map<std::pair<int, int>, int> in_images, in_cloud;
  for (int v = 0; v < classes.rows; ++v)
    for (int u = 0; u < classes.cols; ++u)
      if (classes.at<uint16_t>(v, u) != 65535) ++in_images[{classes.at<uint16_t>(v, u), instances.at<uint16_t>(v, u)}];
  float min_z = 1e9f;
  for (size_t i = 0; i < points; ++i) {
    uint16_t class_id, instance_id;
    float z;
    std::memcpy(&z, body + i * 20 + 8, 4);
    std::memcpy(&class_id, body + i * 20 + 16, 2);
    std::memcpy(&instance_id, body + i * 20 + 18, 2);
    ++in_cloud[{class_id, instance_id}];
    min_z = std::min(min_z, z);
  }
  CHECK(points == 160u * 120u - static_cast<size_t>(cv::countNonZero(classes == 65535)));
  CHECK(in_cloud == in_images);
  CHECK(in_images.size() > 3);  // several objects are in view
  CHECK(min_z > 0);             // sensor frame: every point in front of the camera
}

TEST_CASE("labeled clouds of a frame without a depth reading in range: files of no points, the run goes on") {
  for (const std::string kind : {"pcd", "ply"}) {
    INFO(kind);
    TempDir dir;
    write_text(dir / "job.yaml",
               cloud_job(kind, ", params: {sensors: {rgbd: {min_depth_m: 0.01, max_depth_m: 0.05}}}"));
    const auto run = run_olt("run " + (dir / "job.yaml").string());
    REQUIRE(run.exit_code == 0);
    // Every depth pixel out of range: no pixel labeled.
    const cv::Mat classes = olt::read_grey16(dir / "out/labels/rgbd/class/000001.png");
    CHECK(cv::countNonZero(classes != 65535) == 0);
    const std::string bytes = read_text(dir / ("out/labels/rgbd/clouds/000001." + kind));
    if (kind == "pcd") {
      CHECK_THAT(bytes, Catch::Contains("FIELDS x y z rgb class instance") && Catch::Contains("\nPOINTS 0\n") &&
                            Catch::Contains("DATA binary\n"));
    } else {
      CHECK_THAT(bytes, Catch::StartsWith("ply\nformat binary_little_endian 1.0\n") &&
                            Catch::Contains("\nelement vertex 0\n") && Catch::Contains("property ushort class\n") &&
                            Catch::EndsWith("end_header\n"));
    }
  }
}
