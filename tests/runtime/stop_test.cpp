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

// The cache's locks `names`, held by this process (exclusively) as another olt process would.
std::vector<olt::CacheLock> hold(const fs::path& dir, const std::vector<std::string>& names) {
  std::vector<olt::CacheLock> held;
  for (const auto& name : names) held.emplace_back(dir / "cache", name, nullptr);
  return held;
}

// The 256 locks of stages being made (a stage's key picks one).
std::vector<std::string> stage_locks() {
  std::vector<std::string> names;
  for (int i = 0; i < 256; ++i) names.push_back(olt::format_text("stage-%02x", i));
  return names;
}

// Sends `run` SIGTERM once it says it waits for `what`; its stderr once it ended as killed by it.
std::string stopped_waiting(OltProcess& run, const std::string& what) {
  if (!run.said("waiting for " + what, 120)) FAIL("it did not wait for " << what << ": " << run.err());
  CHECK(run.stop(SIGTERM, 60) == -1);  // it ends while the lock is still held
  INFO(run.err());
  CHECK(run.died_of() == SIGTERM);
  return run.err();
}

// The output of the job (job("{}")) run from nothing, in a folder of its own.
std::string output_from_nothing() {
  TempDir clean;
  write_text(clean / "job.yaml", job("{}"));
  REQUIRE(run_olt("run " + (clean / "job.yaml").string()).exit_code == 0);
  return snapshot(clean / "out");
}

// After a run in `dir` that ended early: nothing published, the cache sound (`olt cache verify`), and
// the next run says `says` and publishes `expected`, byte for byte. Returns the next run's log.
std::string next_run_goes_on(const fs::path& dir, const std::string& says, const std::string& expected) {
  CHECK_FALSE(fs::exists(dir / "out"));
  const auto verify = run_olt("cache verify " + (dir / "job.yaml").string());
  CHECK_THAT(verify.out, Catch::Contains("; 0 damaged"));
  const auto next = run_olt("run " + (dir / "job.yaml").string());
  INFO(next.err);
  REQUIRE(next.exit_code == 0);
  CHECK_THAT(next.err, Catch::Contains(says));
  CHECK(snapshot(dir / "out") == expected);
  return next.err;
}

}  // namespace

TEST_CASE("olt run waiting for a cache lock another process holds stops at SIGTERM") {
  TempDir dir;
  write_text(dir / "job.yaml", job("{}"));
  const std::vector<std::string> run_args = {"run", (dir / "job.yaml").string()};
  const std::string nothing = "; nothing published, the output is as it was";
  {  // `olt cache gc` running (it holds the gc lock that runs share)
    const auto gc = hold(dir.path(), {"gc"});
    OltProcess run(run_args, dir / "gc");
    CHECK_THAT(stopped_waiting(run, "olt cache gc to finish"),
               Catch::Contains("SIGTERM: stopped while waiting for olt cache gc to finish" + nothing));
  }
  {  // another process making the first stage
    const auto making = hold(dir.path(), stage_locks());
    OltProcess run(run_args, dir / "stage");
    const std::string err = stopped_waiting(run, "another olt process using this cache");
    CHECK_THAT(err, Catch::Contains("[1/6] source (source): waiting for another olt process using this cache"));
    CHECK_THAT(err, Catch::Contains("SIGTERM: stopped in stage 'source' (source) while waiting for another olt "
                                    "process using this cache" +
                                    nothing));
  }
  {  // another run publishing once this one made every stage: the stage locks held first, so that it
     // is past its start-of-run publish before this process takes the publish lock (the next run,
     // finding every stage, tells the wait at the end from that one)
    auto making = hold(dir.path(), stage_locks());
    OltProcess run(run_args, dir / "publish");
    if (!run.said("waiting for another olt process using this cache", 120)) FAIL(run.err());
    const auto publishing = hold(dir.path(), {"publish"});
    making.clear();
    CHECK_THAT(stopped_waiting(run, "another run to finish publishing"),
               Catch::Contains("SIGTERM: stopped while waiting for another run to finish publishing" + nothing));
  }
  // The locks free again, the next run finds every stage: the run stopped last made them all.
  const std::string next = next_run_goes_on(dir.path(), "[6/6] dataset (export): cached", output_from_nothing());
  CHECK_THAT(next, !Catch::Contains("): running ("));
}

TEST_CASE("a second SIGTERM while olt run stops ends it at once, and loses nothing") {
  // Both signals as the sixth cache entry's files are written, before it is put in place (a frame's,
  // after the source, calibration, poses, annotations and a frame before it): one thread, so that is
  // the only entry under way.
  TempDir dir;
  write_text(dir / "job.yaml", job("{}"));
  OltProcess run({"run", (dir / "job.yaml").string()}, dir / "twice",
                 {"OLT_FAULT_TERM_AT=artifact_written:6", "OLT_FAULT_TERM_SIGNALS=2", "OLT_THREADS=1"});
  CHECK(run.stop(0, 120) == -1);
  INFO(run.err());
  CHECK(run.died_of() == SIGTERM);
  CHECK_THAT(run.err(), Catch::Contains("fault injection: 2 SIGTERMs at artifact_written (passage 6)"));
  CHECK_THAT(run.err(), Catch::Contains("[5/6] labels (propagate): running"));
  CHECK_THAT(run.err(), !Catch::Contains("stopped in stage"));  // at once, not at its next frame
  CHECK_FALSE(fs::is_empty(dir / "cache/tmp"));                 // the entry it was writing, left half-made
  // The next run clears what was left, finds the frame stored before and labels the rest.
  next_run_goes_on(dir.path(), "labeled 10 observations (9 relabeled, 1 unchanged)", output_from_nothing());
  CHECK(fs::is_empty(dir / "cache/tmp"));
}

TEST_CASE("olt run stopped by SIGTERM mid-labeling publishes nothing, ends by the signal, and the next run resumes") {
  const std::string expected = output_from_nothing();
  TempDir dir;
  write_text(dir / "job.yaml", job("{}"));
  const std::string err = stopped_run(dir.path(), 3);
  CHECK_THAT(err, Catch::Contains("fault injection: SIGTERM at unit_stored (passage 3)"));
  CHECK_THAT(err, Catch::Contains("SIGTERM: stopped in stage 'labels' (propagate) with 7 of 10 frames left to label; "
                                  "nothing published, the output is as it was"));
  // The three frames stored before the signal are found: the run labels the seven left.
  next_run_goes_on(dir.path(), "labeled 10 observations (7 relabeled, 3 unchanged)", expected);

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
