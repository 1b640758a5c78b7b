// Calibration layering: what the recording knows, then the preset, then the job's numbers.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"

using namespace olt::test;
using nlohmann::json;

TEST_CASE("calibrate: recording values - preset - explicit numbers - in that order") {
  TempDir dir;
  write_text(dir / "job.yaml", R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: 2, width: 64, height: 48}}
  preset:
    kind: calibrate
    needs: [source]
    params:
      sensors:
        rgbd: {preset: tum_fr1, depth_intrinsics: [100, 101, 30, 20], max_depth_m: 3, time_offset_s: -0.01,
               pose_on_robot: [0.1, 0, 1.0, 90, 0, 0]}
)");
  const auto result = run_olt("run " + (dir / "job.yaml").string());
  REQUIRE(result.exit_code == 0);
  const json c = json::parse(read_text(dir / "out/preset/calibration.json"))["rgbd"];
  // explicit intrinsics win over the preset; the preset's distortion and depth scale stay
  CHECK(c["depth"]["fx"] == 100);
  CHECK(c["depth"]["cy"] == 20);
  CHECK(c["depth"]["distortion"][0] == 0.2624);
  CHECK(c["depth_scale"] == 5000);
  // the colour camera follows the depth camera unless given; sizes come from the recording
  CHECK(c["color"]["fx"] == 100);
  CHECK(c["depth"]["width"] == 64);
  CHECK(c["max_depth_m"] == 3);
  CHECK(c["min_depth_m"] == 0.1);
  CHECK(c["time_offset_s"] == -0.01);
  // yaw 90 about z: quaternion (0, 0, sin 45, cos 45)
  CHECK(c["T_robot_sensor"][2] == 1.0);
  CHECK(c["T_robot_sensor"][5].get<double>() == Approx(std::sqrt(0.5)));
}

TEST_CASE("calibrate: a TUM recording needs intrinsics from the job") {
  const auto data = shared_data("tum_fr1_rpy");
  if (data.empty()) {
    WARN("skipped: ../shared/data/tum_fr1_rpy is absent");
    return;
  }
  TempDir dir;
  write_text(dir / "job.yaml", "version: 1\noutput: out\nstages:\n  s: {kind: source, params: {format: tum, path: " +
                                   data.string() + "}}\n  c: {kind: calibrate, needs: [s]}\n");
  const auto result = run_olt("validate " + (dir / "job.yaml").string());
  CHECK(result.exit_code == 2);
  CHECK_THAT(result.err, Catch::Contains("sensor 'rgbd' needs a preset or depth_intrinsics"));
}
