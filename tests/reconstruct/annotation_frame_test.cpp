// The annotation frame on a recording whose poses' frame is tilted 20 degrees from gravity (as a
// motion-capture or first-camera frame is): up found within 1 degree of the truth, the origin on
// the floor, and boxes drawn yaw-only in the levelled frame (as labelCloud draws them) label what
// the exact full-rotation boxes label, where yaw-only boxes in the tilted frame do not.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "olt/formats/annotations.h"
#include "olt/reconstruct/level.h"
#include "olt/source/synthetic.h"
#include "support/temp_dir.h"
#include "support/yaw_only.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

// The job labeling into `output` with the annotations stage `annotations`.
std::string job(const std::string& output, const std::string& annotations) {
  return "version: 1\noutput: " + output +
         "\ncache: cache\nstages:\n"
         "  source: {kind: source, params: {format: synthetic, frames: 16, width: 160, height: 120, tilt_deg: 20}}\n"
         "  calibrate: {kind: calibrate, needs: [source]}\n"
         "  poses: {kind: poses, needs: [calibrate]}\n"
         "  scene: {kind: reconstruct, needs: [poses], params: {every: 2}}\n"
         "  annotations: " +
         annotations +
         "\n"
         "  labels: {kind: propagate, needs: [poses, annotations]}\n";
}

void run(const fs::path& dir, const std::string& name, const std::string& text) {
  write_text(dir / (name + ".yaml"), text);
  const auto result = run_olt("run " + (dir / (name + ".yaml")).string());
  INFO(result.err);
  REQUIRE(result.exit_code == 0);
}

}  // namespace

TEST_CASE("a scene tilted 20 degrees: up within 1 degree, origin on the floor, yaw-only boxes label as exact ones") {
  TempDir dir;
  run(dir.path(), "truth", job("truth", "{kind: annotations, needs: [source]}"));
  const auto frame =
      olt::annotation_frame_from_json(nlohmann::json::parse(read_text(dir / "truth/scene/annotation_frame.json")));
  CHECK(frame.method == "support_plane");
  const olt::Pose T_truth_room = olt::synthetic_truth_frame(20);
  const Eigen::Vector3d up = frame.T_world_annotation.linear().col(2), true_up = T_truth_room.linear().col(2);
  INFO("up " << up.transpose() << ", truth " << true_up.transpose());
  CHECK(std::acos(std::min(1.0, up.dot(true_up))) * 180 / M_PI < 1.0);
  CHECK(std::abs(frame.tilt_deg() - 20) < 1.0);
  // The origin on the floor (the room's z = 0), within 2 cm.
  const Eigen::Vector3d origin_in_room = T_truth_room.inverse() * frame.T_world_annotation.translation();
  CHECK(std::abs(origin_in_room.z()) < 0.02);

  const auto exact = olt::read_native_annotations(read_text(dir / "truth/annotations/boxes.json"));
  REQUIRE(exact.size() == 7);
  // Drawn yaw-only in the annotation frame, read with frame: annotation.
  write_text(dir / "levelled.json", olt::format_native_annotations(yaw_only(exact, frame.T_world_annotation)));
  run(dir.path(), "levelled",
      job("levelled", "{kind: annotations, needs: [scene], params: {file: levelled.json, frame: annotation}}"));
  // The same boxes drawn yaw-only in the tilted frame cut through the tilted objects.
  write_text(dir / "tilted.json", olt::format_native_annotations(yaw_only(exact, olt::Pose::Identity())));
  run(dir.path(), "tilted", job("tilted", "{kind: annotations, params: {file: tilted.json, frame: world}}"));

  const double levelled = label_agreement(dir / "truth", dir / "levelled");
  const double tilted = label_agreement(dir / "truth", dir / "tilted");
  INFO("agreement with the exact boxes: yaw-only in the annotation frame " << levelled << ", in the tilted frame "
                                                                           << tilted);
  CHECK(levelled >= 0.995);
  CHECK(tilted < 0.95);
}

TEST_CASE("frame: annotation needs a file and a reconstruct stage upstream, said at the key") {
  TempDir dir;
  write_text(dir / "job.yaml", job("out", "{kind: annotations, params: {file: boxes.json, frame: annotation}}"));
  write_text(dir / "boxes.json", R"({"version": 1, "boxes": []})");
  const auto result = run_olt("validate " + (dir / "job.yaml").string());
  CHECK(result.exit_code == 2);
  CHECK_THAT(result.err, Catch::Contains("job.yaml:9:") && Catch::Contains("needs a reconstruct stage upstream"));
}

// A job that publishes a levelled scene and reads a box file without saying its frame: it could be
// either, so validation asks (a silent guess would label the wrong pixels).
TEST_CASE("a box file beside a levelled scene must say its frame") {
  TempDir dir;
  write_text(dir / "job.yaml", job("out", "{kind: annotations, params: {file: boxes.json}}"));
  write_text(dir / "boxes.json", R"({"version": 1, "boxes": []})");
  const auto result = run_olt("validate " + (dir / "job.yaml").string());
  CHECK(result.exit_code == 2);
  CHECK_THAT(result.err, Catch::Contains("job.yaml:9:") && Catch::Contains("say which frame the boxes of") &&
                             Catch::Contains("frame: annotation") && Catch::Contains("frame: world"));
  write_text(dir / "job.yaml", job("out", "{kind: annotations, params: {file: boxes.json, frame: world}}"));
  CHECK(run_olt("validate " + (dir / "job.yaml").string()).exit_code == 0);
}

// Robot@Home's cameras are mounted on their side (portrait): their optical -y is horizontal. The
// frame of a robot's poses is level (its laser), and the levelling must find that, not a wall.
TEST_CASE("a robot with cameras on their side: the scene is levelled on its floor, not on a wall") {
  TempDir dir;
  write_text(dir / "job.yaml",
             "version: 1\noutput: out\ncache: cache\nstages:\n"
             "  source: {kind: source, params: {format: synthetic, cameras: 1, frames: 30, width: 160, height: 120}}\n"
             "  calibrate: {kind: calibrate, needs: [source]}\n"
             "  poses: {kind: poses, needs: [calibrate]}\n"
             "  scene: {kind: reconstruct, needs: [poses], params: {every: 2}}\n");
  run(dir.path(), "job", read_text(dir / "job.yaml"));
  const auto frame =
      olt::annotation_frame_from_json(nlohmann::json::parse(read_text(dir / "out/scene/annotation_frame.json")));
  CHECK(frame.method == "support_plane");
  CHECK(frame.tilt_deg() < 1.0);
  CHECK(std::abs(frame.T_world_annotation.translation().z()) < 0.02);  // the floor is z = 0
}
