// Killed anywhere, nothing lost: a run of every stage kind is killed with SIGKILL at its fault points
// (olt/core/fault.h: every cache entry before and after it is put in place, log lines, output files
// as they are staged, just before and just after the publish is committed, and as they are moved into place), then run
// again; every time the output is byte-identical to a clean run's and `olt cache verify` finds no damaged entry. The
// moments are named, not timed, so a busy machine changes nothing. Cache entries are killed in a chain: each run
// resumes what the killed one left and is killed at its next entry, until one finishes; so every entry is killed once
// (before, and after, its rename) and each kill costs one entry's work instead of a run's from nothing.
#include <catch2/catch.hpp>

#include "support/process.h"
#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

const char* kJob = R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: 10, width: 200, height: 150}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  scene: {kind: reconstruct, needs: [poses], params: {every: 2}}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations]}
  dataset: {kind: export, needs: [labels]}
  report: {kind: report, needs: [labels, scene]}
)";

void start_from_nothing(const fs::path& dir) {
  fs::remove_all(dir / "out");
  fs::remove_all(dir / "cache");
}

// Runs the job, killed at the `passage`-th passage of fault point `where`; true where it died there,
// false where the run had fewer passages and finished.
// `one_thread`: frames one at a time, so the passages come in one order.
bool killed_at(const fs::path& dir, const std::string& where, int passage, bool one_thread = false) {
  std::vector<std::string> env = {"OLT_FAULT_KILL_AT=" + where + ":" + std::to_string(passage)};
  if (one_thread) env.push_back("OLT_THREADS=1");
  OltProcess victim({"run", (dir / "job.yaml").string()}, dir / "victim", env);
  const int exit_code = victim.stop(0, 120);  // signal 0: wait for its own end
  INFO(victim.err());
  if (exit_code == 0) {
    CHECK(victim.err().find("fault injection") == std::string::npos);
    return false;
  }
  CHECK(exit_code == -1);
  CHECK_THAT(victim.err(), Catch::Contains("fault injection: killed at " + where));
  return true;
}

}  // namespace

TEST_CASE("a run killed with SIGKILL at its fault points resumes to the same bytes with no damaged cache entry") {
  TempDir dir;
  write_text(dir / "job.yaml", kJob);
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  const std::string expected = snapshot(dir / "out");

  // Every cache entry (8 stages, 10 frames) before its rename (a run killed at its first entry
  // stores none, so the chain's runs are killed at their second: the first is what the previous
  // run was killed at) and after it. One thread: a run stores at most one entry before its kill, so
  // the chain kills at every entry.
  for (const auto& [where, passage] :
       std::vector<std::pair<std::string, int>>{{"artifact_written", 2}, {"artifact_stored", 1}}) {
    start_from_nothing(dir.path());
    int kills = where == "artifact_written" && killed_at(dir.path(), where, 1, true);  // the very first entry
    while (kills < 100 && killed_at(dir.path(), where, passage, true)) {
      ++kills;
      const auto verify = run_olt("cache verify " + (dir / "job.yaml").string());
      INFO("killed at " << where << ", kill " << kills << "; " << verify.out);
      CHECK(verify.exit_code == 0);
      CHECK_THAT(verify.out, Catch::Contains("; 0 damaged"));
    }
    INFO(where);
    CHECK(kills >= 18);
    CHECK(snapshot(dir / "out") == expected);  // the run that finished resumed the chain
  }

  // Every 4th stored unit, every 7th staged output file, every 3rd log line, just before the publish
  // is committed, every 17th file moved into place: each from nothing, then run again. Just after
  // the commit (no change made yet): over the last output (one file of it removed), from an empty cache. The run again
  // also removes what the killed one left beside the output.
  for (const auto& [where, step] : std::vector<std::pair<std::string, int>>{{"unit_stored", 4},
                                                                            {"published_file", 7},
                                                                            {"log_appended", 3},
                                                                            {"manifest_next", 1},
                                                                            {"publish_committed", 1},
                                                                            {"file_moved", 17}}) {
    const auto fresh = [&, where = where] {
      // A file of the last output removed: an output that is whole is not published again.
      if (where == "publish_committed") return fs::remove_all(dir / "cache"), fs::remove(dir / "out/labels.json"), true;
      return start_from_nothing(dir.path()), true;
    };
    int kills = 0;
    for (int passage = 1; passage < 1000 && fresh() && killed_at(dir.path(), where, passage); passage += step) {
      ++kills;
      const auto again = run_olt("run " + (dir / "job.yaml").string());
      INFO("killed at " << where << " passage " << passage << "; " << again.err);
      REQUIRE(again.exit_code == 0);
      CHECK(snapshot(dir / "out") == expected);
      for (const auto& e : fs::directory_iterator(dir.path()))
        CHECK(e.path().filename().string().rfind(".tmp.", 0) == std::string::npos);
      const auto verify = run_olt("cache verify " + (dir / "job.yaml").string());
      INFO(verify.out);
      CHECK(verify.exit_code == 0);
      CHECK_THAT(verify.out, Catch::Contains("; 0 damaged"));
    }
    INFO(where);
    CHECK(kills >= (where == "manifest_next" || where == "publish_committed" ? 1 : 3));
  }
}
