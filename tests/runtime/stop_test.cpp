// `olt run` asked to stop (SIGTERM: Slurm at a job's time limit, Kubernetes stopping a pod; SIGINT:
// Ctrl-C) stops at its next frame or stage: it publishes nothing, keeps and syncs what it finished,
// and ends as killed by the signal, so a shell or Slurm sees what happened. The signal comes from the
// process itself at a named moment (olt/core/fault.h), not from a timer.
#include <catch2/catch.hpp>
#include <csignal>

#include "olt/cache/lock.h"
#include "olt/core/text.h"
#include "support/process.h"
#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

std::string job(const std::string& labels_params) {
  return R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: 10, width: 160, height: 120}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations], params: )" +
         labels_params + R"(}
  dataset: {kind: export, needs: [labels]}
)";
}

// `olt run` of the job in `dir`, sent SIGTERM by itself as it stores its `passage`-th frame; one
// thread, so frames are stored one at a time. Returns its stderr once it ended as killed by SIGTERM.
std::string stopped_run(const fs::path& dir, int passage) {
  OltProcess run({"run", (dir / "job.yaml").string()}, dir / ("stopped-at-" + std::to_string(passage)),
                 {"OLT_FAULT_TERM_AT=unit_stored:" + std::to_string(passage), "OLT_THREADS=1"});
  CHECK(run.stop(0, 120) == -1);
  INFO(run.err());
  CHECK(run.died_of() == SIGTERM);
  return run.err();
}

// `olt run` of the job in `dir` while this process holds the cache's locks `names` (exclusively), sent
// SIGTERM once it says it waits for `waiting_for`. Returns its stderr once it ended as killed by it.
std::string stopped_waiting(const fs::path& dir, const std::vector<std::string>& names,
                            const std::string& waiting_for) {
  std::vector<olt::CacheLock> held;
  for (const auto& name : names) held.emplace_back(dir / "cache", name, nullptr);
  OltProcess run({"run", (dir / "job.yaml").string()}, dir / ("waiting-" + names.front()));
  INFO(run.err());
  REQUIRE(run.said("waiting for " + waiting_for, 120));
  CHECK(run.stop(SIGTERM, 60) == -1);  // it ended while the locks are still held
  CHECK(run.died_of() == SIGTERM);
  return run.err();
}

}  // namespace

TEST_CASE("olt run waiting for a cache lock another process holds stops at SIGTERM") {
  TempDir dir;
  write_text(dir / "job.yaml", job("{}"));
  const std::string nothing = "; nothing published, the output is as it was";
  // `olt cache gc` running (it holds the gc lock that runs share).
  CHECK_THAT(stopped_waiting(dir.path(), {"gc"}, "olt cache gc to finish"),
             Catch::Contains("SIGTERM: stopped while waiting for olt cache gc to finish" + nothing));
  // Another run publishing.
  CHECK_THAT(stopped_waiting(dir.path(), {"publish"}, "another run to finish publishing"),
             Catch::Contains("SIGTERM: stopped while waiting for another run to finish publishing" + nothing));
  // Another process making the first stage (its key's lock is one of 256: all of them held).
  std::vector<std::string> stages;
  for (int i = 0; i < 256; ++i) stages.push_back(olt::format_text("stage-%02x", i));
  const std::string err = stopped_waiting(dir.path(), stages, "another olt process using this cache");
  CHECK_THAT(err, Catch::Contains("[1/6] source (source): waiting for another olt process using this cache"));
  CHECK_THAT(err, Catch::Contains("SIGTERM: stopped in stage 'source' (source) while waiting for another olt process "
                                  "using this cache" +
                                  nothing));
  CHECK_FALSE(fs::exists(dir / "out"));
  // The locks free again, a run goes through.
  const auto run = run_olt("run " + (dir / "job.yaml").string());
  INFO(run.err);
  CHECK(run.exit_code == 0);
  CHECK(fs::exists(dir / "out/labels"));
}

TEST_CASE("a second SIGTERM while olt run stops ends it at once, and loses nothing") {
  TempDir clean;
  write_text(clean / "job.yaml", job("{}"));
  REQUIRE(run_olt("run " + (clean / "job.yaml").string()).exit_code == 0);

  TempDir dir;
  write_text(dir / "job.yaml", job("{}"));
  OltProcess run({"run", (dir / "job.yaml").string()}, dir / "twice",
                 {"OLT_FAULT_TERM_AT=unit_stored:3", "OLT_FAULT_TERM_SIGNALS=2", "OLT_THREADS=1"});
  CHECK(run.stop(0, 120) == -1);
  INFO(run.err());
  CHECK(run.died_of() == SIGTERM);
  CHECK_THAT(run.err(), Catch::Contains("fault injection: 2 SIGTERMs at unit_stored (passage 3)"));
  CHECK_THAT(run.err(), !Catch::Contains("stopped in stage"));  // at once, not at its next frame
  CHECK_FALSE(fs::exists(dir / "out"));
  const auto verify = run_olt("cache verify " + (dir / "job.yaml").string());
  CHECK_THAT(verify.out, Catch::Contains("; 0 damaged"));
  // The three frames stored before it ended are found; the output is a run's from nothing.
  const auto resumed = run_olt("run " + (dir / "job.yaml").string());
  INFO(resumed.err);
  REQUIRE(resumed.exit_code == 0);
  CHECK_THAT(resumed.err, Catch::Contains("labeled 10 observations (7 relabeled, 3 unchanged)"));
  CHECK(snapshot(dir / "out") == snapshot(clean / "out"));
}

TEST_CASE("olt run stopped by SIGTERM mid-labeling publishes nothing, ends by the signal, and the next run resumes") {
  TempDir clean;
  write_text(clean / "job.yaml", job("{}"));
  REQUIRE(run_olt("run " + (clean / "job.yaml").string()).exit_code == 0);

  TempDir dir;
  write_text(dir / "job.yaml", job("{}"));
  const std::string err = stopped_run(dir.path(), 3);
  CHECK_THAT(err, Catch::Contains("fault injection: SIGTERM at unit_stored (passage 3)"));
  CHECK_THAT(err, Catch::Contains("SIGTERM: stopped in stage 'labels' (propagate) with 7 of 10 frames left to label; "
                                  "nothing published, the output is as it was"));
  CHECK_FALSE(fs::exists(dir / "out"));
  const auto verify = run_olt("cache verify " + (dir / "job.yaml").string());
  CHECK_THAT(verify.out, Catch::Contains("; 0 damaged"));

  // The three frames stored before the signal are found: the run labels the seven left, and its
  // output is a run's from nothing, byte for byte.
  const auto resumed = run_olt("run " + (dir / "job.yaml").string());
  INFO(resumed.err);
  REQUIRE(resumed.exit_code == 0);
  CHECK_THAT(resumed.err, Catch::Contains("labeled 10 observations (7 relabeled, 3 unchanged)"));
  const std::string expected = snapshot(clean / "out");
  CHECK(snapshot(dir / "out") == expected);

  // An edit stopped the same way leaves the last output in place.
  write_text(dir / "job.yaml", job("{color_fill_px: 4}"));
  CHECK_THAT(stopped_run(dir.path(), 2), Catch::Contains("with 8 of 10 frames left to label"));
  CHECK(snapshot(dir / "out") == expected);

  // A signal once publishing has begun (the output removed, so every file is published again): the
  // run finishes, exit 0, the output whole.
  write_text(dir / "job.yaml", job("{}"));
  fs::remove_all(dir / "out");
  OltProcess late({"run", (dir / "job.yaml").string()}, dir / "late", {"OLT_FAULT_TERM_AT=published_file:1"});
  const int exit_code = late.stop(0, 120);
  INFO(late.err());
  CHECK(exit_code == 0);
  CHECK_THAT(late.err(), Catch::Contains("fault injection: SIGTERM at published_file"));
  CHECK_THAT(late.err(), !Catch::Contains("stopped"));
  CHECK(snapshot(dir / "out") == expected);
}
