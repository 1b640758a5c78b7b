// The content cache end to end on small synthetic recordings, through the olt binary.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <set>

#include "olt/core/hash.h"
#include "support/temp_dir.h"

using namespace olt::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kStages = {"source", "calibrate", "poses", "scene", "annotations", "labels"};

const char* kJob = R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: 6, width: 160, height: 120}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  scene: {kind: reconstruct, needs: [poses], params: {every: 2, preview_size_px: 100}}
  annotations: {kind: annotations, needs: [source], params: {file: boxes.json, frame: world}}
  labels: {kind: propagate, needs: [poses, annotations]}
)";

std::map<std::string, std::string> plan(const fs::path& job, std::map<std::string, std::string>* reasons = nullptr) {
  Plan p = plan_of(job);
  if (reasons) *reasons = p.reason;
  return p.status;
}

}  // namespace

TEST_CASE("second run executes nothing - outputs byte-identical - edits re-run exactly what they touch") {
  TempDir dir;
  // Boxes: those of the synthetic room (a first run with the recording's own boxes publishes them).
  write_text(
      dir / "bootstrap.yaml",
      std::string(kJob).replace(std::string(kJob).find("params: {file: boxes.json, frame: world}"), 40, "params: {}"));
  REQUIRE(run_olt("run " + (dir / "bootstrap.yaml").string()).exit_code == 0);
  fs::copy_file(dir / "out/annotations/boxes.json", dir / "boxes.json");
  fs::remove_all(dir / "out");
  write_text(dir / "job.yaml", kJob);
  const fs::path job = dir / "job.yaml";

  std::map<std::string, std::string> reasons;
  auto status = plan(job, &reasons);
  CHECK(status["source"] == "cached");  // same source params as the bootstrap job: shared cache entry
  CHECK(status["annotations"] == "run");
  CHECK(reasons["annotations"] == "never run");

  auto first = run_olt("run " + job.string());
  REQUIRE(first.exit_code == 0);
  const auto manifest = json::parse(read_text(dir / "out/manifest.json"));
  std::set<std::string> kinds;
  for (const auto& f : manifest["files"]) {
    kinds.insert(f["kind"].get<std::string>());
    CHECK(olt::sha256_file(dir / "out" / f["path"].get<std::string>()) == f["sha256"]);
  }
  for (const char* kind :
       {"trajectory", "scene_ply", "scene_pcd", "class_label", "instance_label", "overlay", "label_map"})
    CHECK(kinds.count(kind));
  const std::string before = snapshot(dir / "out");

  for (const auto& [id, s] : plan(job)) CHECK(s == "cached");
  // Nothing to do writes nothing: the output folder and the stages' records stay the same files.
  std::map<fs::path, fs::file_time_type> written;
  for (const auto& e : fs::recursive_directory_iterator(dir / "cache/records")) written[e.path()] = e.last_write_time();
  struct stat output_before {};
  ::stat((dir / "out").c_str(), &output_before);
  auto second = run_olt("run " + job.string());
  REQUIRE(second.exit_code == 0);
  CHECK_THAT(second.err, Catch::Contains("6 stages: 0 ran, 6 cached"));
  CHECK(snapshot(dir / "out") == before);
  struct stat output_after {};
  ::stat((dir / "out").c_str(), &output_after);
  CHECK(output_after.st_ino == output_before.st_ino);
  REQUIRE_FALSE(written.empty());
  for (const auto& [file, time] : written) CHECK(fs::last_write_time(file) == time);

  SECTION("changing a stage's params re-runs that stage only") {
    std::string text = kJob;
    text.replace(text.find("every: 2"), 8, "every: 3");
    write_text(job, text);
    status = plan(job, &reasons);
    CHECK(status == only_running(kStages, {"scene"}));
    CHECK(reasons["scene"] == "params changed: every");
  }
  SECTION("an edit that leaves the normalised boxes unchanged stops at the annotations stage") {
    const auto boxes = json::parse(read_text(dir / "boxes.json"));
    write_text(dir / "boxes.json", boxes.dump(4));  // same boxes, different bytes
    status = plan(job, &reasons);
    CHECK(status["annotations"] == "run");
    CHECK(reasons["annotations"] == "file " + (dir / "boxes.json").string() + " changed");
    // The plan runs the (light) annotations stage aside, so it already sees the same boxes.
    CHECK(status["labels"] == "cached");
    const auto rerun = run_olt("run " + job.string());
    REQUIRE(rerun.exit_code == 0);
    CHECK_THAT(rerun.err, Catch::Contains("labels (propagate): cached"));
    CHECK(snapshot(dir / "out") == before);
  }
  SECTION("moving one box re-runs annotations and propagation only; labels change") {
    auto boxes = json::parse(read_text(dir / "boxes.json"));
    boxes["boxes"][0]["center"][0] = boxes["boxes"][0]["center"][0].get<double>() + 0.3;
    write_text(dir / "boxes.json", boxes.dump(1));
    status = plan(job, &reasons);
    CHECK(status == only_running(kStages, {"annotations", "labels"}));
    const auto rerun = run_olt("run " + job.string());
    REQUIRE(rerun.exit_code == 0);
    CHECK_THAT(rerun.err, Catch::Contains("6 stages: 2 ran, 4 cached"));
    CHECK(snapshot(dir / "out") != before);
    // and back: the original boxes are still in the cache, so nothing runs but the file stage
    write_text(dir / "boxes.json", read_text(dir / "out/annotations/boxes.json"));
  }
}
