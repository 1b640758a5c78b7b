// The synthetic robot end to end: laser map, laser poses for two cameras (with and without
// refinement by registration), labels; judged against the exact truth.
#include <catch2/catch.hpp>

#include "support/synthetic_truth.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

SyntheticConfig robot_config() {
  SyntheticConfig c;
  c.cameras = 2;
  c.frames = 16;
  c.rate_hz = 2.5;
  c.width = 160;
  c.height = 120;
  return c;
}

std::string robot_job(const std::string& poses_params) {
  return R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, cameras: 2, frames: 16, rate_hz: 2.5, width: 160, height: 120}}
  calibrate: {kind: calibrate, needs: [source]}
  laser_map: {kind: laser_map, needs: [source]}
  poses: {kind: poses, needs: [calibrate, laser_map], params: )" +
         poses_params + R"(}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations], params: {overlays: false, color_labels: false}}
)";
}

}  // namespace

TEST_CASE("synthetic robot, laser poses: cameras within 1 cm and 0.2 degrees, labels >= 99% exact", "[heavy]") {
  TempDir dir;
  write_text(dir / "job.yaml", robot_job("{method: laser, anchor_to_groundtruth: true}"));
  const Completed run = run_olt("run " + (dir / "job.yaml").string());
  REQUIRE(run.exit_code == 0);
  const SyntheticJudgement j = judge_synthetic_run(dir / "out", "poses", robot_config());
  CHECK(j.observations == 32);
  CHECK(j.translation_max_m < 0.01);
  CHECK(j.rotation_max_deg < 0.2);
  CHECK(j.depth_pixels > 32 * 160 * 120 / 2);
  CHECK(j.label_agreement >= 0.99);
  // The map's trajectory and picture are published.
  const std::string manifest = read_text(dir / "out/manifest.json");
  CHECK(manifest.find("\"robot_trajectory\"") != std::string::npos);
  CHECK(manifest.find("\"laser_map_image\"") != std::string::npos);
}

TEST_CASE("synthetic robot, laser poses refined by registration: labels >= 98% exact", "[heavy]") {
  TempDir dir;
  write_text(dir / "job.yaml", robot_job("{method: laser, refine: registration, anchor_to_groundtruth: true}"));
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  const SyntheticJudgement j = judge_synthetic_run(dir / "out", "poses", robot_config());
  CHECK(j.observations >= 28);
  CHECK(j.label_agreement >= 0.98);
}

TEST_CASE("method laser without a map, and a malformed scans file, are refused with the field or line") {
  TempDir dir;
  write_text(dir / "job.yaml", R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, cameras: 1, frames: 2}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate], params: {method: laser}}
)");
  Completed run = run_olt("run " + (dir / "job.yaml").string());
  CHECK(run.exit_code == 2);
  CHECK(run.err.find("job.yaml:7:") != std::string::npos);
  CHECK(run.err.find("method laser needs a map") != std::string::npos);

  write_text(dir / "scans.txt", "0 1 0 0 0 0 3.14 1 80 2 1.0 1.0 1 1\n1 2 0 0 0 0 3.14 1 80 2 1.0 1\n");
  write_text(dir / "laser.yaml", R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: laser_text, scans: scans.txt}}
  laser_map: {kind: laser_map, needs: [source]}
)");
  run = run_olt("run " + (dir / "laser.yaml").string());
  CHECK(run.exit_code == 2);
  CHECK(run.err.find("scans.txt:2:1: N = 2 rays needs 14 fields, got 12") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out"));
}
