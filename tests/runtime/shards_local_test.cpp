// Four shards as parallel local processes on one cache, one killed midway and run again: the merge
// refuses while it is missing, and then publishes the same bytes as a run without shards.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <nlohmann/json.hpp>

#include "support/process.h"
#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

std::string job_text(const std::string& cache) {
  return R"(version: 1
output: out
cache: )" +
         cache + R"(
stages:
  source: {kind: source, params: {format: synthetic, frames: 40, width: 320, height: 240}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  scene: {kind: reconstruct, needs: [poses], params: {every: 4}}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations]}
  dataset: {kind: export, needs: [labels]}
  report: {kind: report, needs: [labels, scene]}
)";
}

// Waits for the process's own end (signal 0 sends none): -1 is a death by signal.
bool signalled_or_killed(OltProcess& p) { return p.stop(0, 120) == -1; }

}  // namespace

TEST_CASE("4 local shards on one cache, one killed midway and re-run, merge to the bytes of a plain run", "[heavy]") {
  TempDir dir;
  const fs::path job = dir / "job.yaml";
  write_text(job, job_text("cache-plain"));
  const auto plain = run_olt("run " + job.string());
  REQUIRE(plain.exit_code == 0);
  const std::string expected = snapshot(dir / "out");
  fs::remove_all(dir / "out");

  write_text(job, job_text("cache-shared"));
  // Shard 2 alone first, killed (by its own fault point: no timer) once 3 of its 10 frames are stored.
  {
    OltProcess victim({"run", job.string(), "--shard=2/4"}, dir / "victim", {"OLT_FAULT_KILL_AT=unit_stored:3"});
    const bool killed = signalled_or_killed(victim);
    INFO(victim.err());
    REQUIRE(killed);
    CHECK_THAT(victim.err(), Catch::Contains("the frames of shard 2/4"));
  }
  // The other three in parallel, on the same cache.
  {
    std::vector<std::unique_ptr<OltProcess>> shards;
    for (int i : {0, 1, 3})
      shards.push_back(std::make_unique<OltProcess>(
          std::vector<std::string>{"run", job.string(), "--shard=" + std::to_string(i) + "/4"},
          dir / ("shard" + std::to_string(i))));
    for (auto& s : shards) {
      INFO(s->err());
      CHECK(s->stop(0, 120) == 0);  // signal 0: just wait
    }
  }
  const auto refused = run_olt("merge " + job.string());
  CHECK(refused.exit_code == 3);
  CHECK_THAT(refused.err, Catch::Contains("shard 2/4 of") && Catch::Contains("has not finished"));
  CHECK_FALSE(fs::exists(dir / "out/manifest.json"));

  const auto rerun = run_olt("run " + job.string() + " --shard=2/4");
  INFO(rerun.err);
  REQUIRE(rerun.exit_code == 0);
  const auto merged = run_olt("merge " + job.string());
  INFO(merged.err);
  REQUIRE(merged.exit_code == 0);
  CHECK(snapshot(dir / "out") == expected);

  // Re-running a finished shard does nothing new; an edit makes the old shards stale for the merge.
  const auto again = run_olt("run " + job.string() + " --shard=0/4");
  CHECK(again.exit_code == 0);
  CHECK_THAT(again.err, Catch::Contains("0 frames labeled, "));
  write_text(job, job_text("cache-shared") + "# edited\n  extra: {kind: annotations, needs: [source]}\n");
  const auto stale = run_olt("merge " + job.string());
  CHECK(stale.exit_code == 3);
  CHECK_THAT(stale.err, Catch::Contains("ran on other inputs"));
}

TEST_CASE("olt plan --units lists every frame once, in order, with its shard") {
  TempDir dir;
  write_text(dir / "job.yaml", job_text("cache"));
  const auto plan = run_olt("plan --units --json --shards=3 " + (dir / "job.yaml").string());
  INFO(plan.err);
  REQUIRE(plan.exit_code == 0);
  const auto units = nlohmann::json::parse(plan.out)["units"];
  int frames = 0;
  std::map<std::string, std::string> shard_of_stage;
  for (const auto& u : units) {
    if (u["scope"] == "frame") {
      CHECK(u["frame"] == "rgbd/" + std::string(6 - std::to_string(frames).size(), '0') + std::to_string(frames));
      CHECK(u["shard"] == frames % 3);
      ++frames;
    } else {
      shard_of_stage[u["stage"]] = u["shard"].dump();
    }
  }
  CHECK(frames == 40);
  CHECK(shard_of_stage["poses"] == "\"any\"");
  CHECK(shard_of_stage["scene"] == "0");
  CHECK(shard_of_stage["dataset"] == "\"merge\"");
  CHECK(shard_of_stage["report"] == "\"merge\"");
  CHECK_FALSE(fs::exists(dir / "out"));  // planning writes no output
}
