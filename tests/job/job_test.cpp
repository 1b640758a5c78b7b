// Job validation: every problem reported at once as FILE:LINE:COLUMN, exit 2, nothing written.
#include "olt/job/job.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"
#include "olt/stages/stage.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

std::string errors_of(const fs::path& job) {
  try {
    load_job(job, kind_specs());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a job with several mistakes gets all of them - each with its position") {
  TempDir dir;
  write_text(dir / "job.yaml", R"(version: 1
output: out
stages:
  source:
    kind: source
    params:
      format: tum
      path: nowhere
  scene:
    kind: reconstruct
    needs: [source, posez]
    params:
      voxel_siz_m: 0.1
      every: "three"
  extra:
    kind: propagat
)");
  const std::string e = errors_of(dir / "job.yaml");
  const std::string file = (dir / "job.yaml").string();
  CHECK_THAT(e, Catch::Contains(file + ":8:13: stage 'source' (source): parameter 'path': 'nowhere' does not exist"));
  CHECK_THAT(e, Catch::Contains(file + ":11:21: stage 'scene': needs 'posez', which is not a stage of this job"));
  CHECK_THAT(e, Catch::Contains(file + ":13:7: stage 'scene' (reconstruct): unknown parameter 'voxel_siz_m'; did you "
                                       "mean 'voxel_size_m'?"));
  CHECK_THAT(e, Catch::Contains(file + ":14:14: stage 'scene' (reconstruct): parameter 'every': expected an integer, "
                                       "got \"three\""));
  CHECK_THAT(e, Catch::Contains(file + ":16:11: stage 'extra': unknown kind 'propagat'; did you mean 'propagate'?"));
}

TEST_CASE("cycles - ranges - unknown top-level keys and missing upstream kinds") {
  TempDir dir;
  write_text(dir / "job.yaml", R"(version: 1
output: out
cach: c
stages:
  a:
    kind: source
    needs: [b]
    params: {format: synthetic, frames: 0}
  b:
    kind: calibrate
    needs: [a]
)");
  const std::string e = errors_of(dir / "job.yaml");
  CHECK_THAT(e, Catch::Contains(":7:") && Catch::Contains("cycle in needs: a -> b -> a"));
  CHECK_THAT(e, Catch::Contains(":8:") && Catch::Contains("parameter 'frames': expected in [1, 100000], got 0"));
  CHECK_THAT(e, Catch::Contains(":3:1:") && Catch::Contains("cach"));

  write_text(dir / "job2.yaml", "version: 1\noutput: out\nstages:\n  p:\n    kind: poses\n");
  CHECK_THAT(errors_of(dir / "job2.yaml"),
             Catch::Contains(":4:3:") && Catch::Contains("needs a 'source' stage upstream"));
  write_text(dir / "job3.yaml", "version: 1\noutput: [\n");
  CHECK_THAT(errors_of(dir / "job3.yaml"), Catch::Contains("job3.yaml:") && Catch::Contains("YAML syntax error"));
}

TEST_CASE("a valid job: paths resolved against the job's folder - defaults filled - dependency order") {
  TempDir dir;
  write_text(dir / "sub/job.yaml", R"(version: 1
output: ../out
cache: ../cache
stages:
  z_source: {kind: source, params: {format: synthetic}}
  a_cal: {kind: calibrate, needs: [z_source]}
)");
  const Job job = load_job(dir / "sub/job.yaml", kind_specs());
  CHECK(job.output == (dir.path() / "out").lexically_normal());
  CHECK(job.cache == (dir.path() / "cache").lexically_normal());
  REQUIRE(job.stages.size() == 2);
  CHECK(job.stages[0].id == "z_source");
  CHECK(job.stages[0].params["frames"] == 30);
  CHECK(job.stage("a_cal").inputs.at("source") == "z_source");
}

TEST_CASE("olt validate and olt run exit 2 on an invalid job and write nothing") {
  TempDir dir;
  write_text(dir / "job.yaml",
             "version: 1\noutput: out\ncache: cache\nstages:\n  s:\n    kind: source\n    params: {format: synthetic, "
             "frame: 3}\n");
  const auto validate = run_olt("validate " + (dir / "job.yaml").string());
  CHECK(validate.exit_code == 2);
  CHECK_THAT(validate.err,
             Catch::Contains("job.yaml:7:33: stage 's' (source): unknown parameter 'frame'; did you mean 'frames'?"));
  const auto run = run_olt("run " + (dir / "job.yaml").string());
  CHECK(run.exit_code == 2);
  CHECK_FALSE(fs::exists(dir / "out"));
  CHECK_FALSE(fs::exists(dir / "cache"));
  CHECK(run_olt("nonsense").exit_code == 2);
  CHECK(run_olt("run --bogus x").exit_code == 2);
  const auto help = run_olt("plan --help");
  CHECK(help.exit_code == 0);
  CHECK_THAT(help.out, Catch::Contains("olt plan JOB [--json]"));
}

TEST_CASE("a job has one propagate stage: labels.json is written at the output root") {
  TempDir dir;
  write_text(dir / "job.yaml", R"(version: 1
output: out
stages:
  s: {kind: source, params: {format: synthetic}}
  c: {kind: calibrate, needs: [s]}
  p: {kind: poses, needs: [c]}
  a: {kind: annotations, needs: [s]}
  l1: {kind: propagate, needs: [p, a]}
  l2: {kind: propagate, needs: [p, a]}
)");
  CHECK_THAT(errors_of(dir / "job.yaml"),
             Catch::Contains("job.yaml:9:14:") && Catch::Contains("a job has one propagate stage"));
}

TEST_CASE("a job's steps: stages next to each other in its order that need and read none of each other") {
  TempDir dir;
  // In the order: annotations (needs nothing), source; calibrate; poses; labels; dataset (reads the
  // labels), scene (reads the poses); report (reads the labels and the scene).
  write_text(dir / "job.yaml", R"(version: 1
output: out
stages:
  source: {kind: source, params: {format: synthetic}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  scene: {kind: reconstruct, needs: [poses]}
  annotations: {kind: annotations, params: {file: boxes.json, frame: world}}
  labels: {kind: propagate, needs: [poses, annotations]}
  dataset: {kind: export, needs: [labels]}
  report: {kind: report, needs: [labels, scene]}
)");
  write_text(dir / "boxes.json", R"({"boxes": []})");
  const Job job = load_job(dir / "job.yaml", kind_specs());
  std::vector<std::vector<std::string>> steps;
  for (const auto& step : stage_steps(job)) {
    steps.emplace_back();
    for (const size_t i : step) steps.back().push_back(job.stages[i].id);
  }
  const std::vector<std::vector<std::string>> expected = {
      {"annotations", "source"}, {"calibrate"}, {"poses"}, {"labels"}, {"dataset", "scene"}, {"report"}};
  CHECK(steps == expected);
}

TEST_CASE("a job's steps: a stage that only needs another (reads nothing of it) is not beside it") {
  TempDir dir;
  write_text(dir / "job.yaml", R"(version: 1
output: out
stages:
  source: {kind: source, params: {format: synthetic}}
  calibrate: {kind: calibrate, needs: [source]}
  annotations: {kind: annotations, needs: [source, calibrate]}
)");
  const Job job = load_job(dir / "job.yaml", kind_specs());
  const auto steps = stage_steps(job);
  REQUIRE(steps.size() == 3);  // the annotations read the source's boxes, and wait for calibrate as told
  for (size_t k = 0; k < 3; ++k) CHECK(steps[k] == std::vector<size_t>{k});
}
