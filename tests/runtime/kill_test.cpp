// Killed anywhere, nothing lost: a run of every stage kind is killed with SIGKILL at 20 moments
// spread over a clean run's duration, then run again; every time the output is byte-identical to a
// clean run's and `olt cache verify` finds no damaged entry.
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <thread>

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

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

TEST_CASE("a run killed with SIGKILL at 20 moments resumes to the same bytes with no damaged cache entry") {
  TempDir dir;
  const fs::path job = dir / "job.yaml";
  write_text(job, kJob);
  // The moments are spread over the run's work, after start-up (loading the shared libraries and
  // the job, as long as `olt validate` takes).
  auto start = std::chrono::steady_clock::now();
  REQUIRE(run_olt("validate " + job.string()).exit_code == 0);
  const double startup_s = seconds_since(start);
  REQUIRE(run_olt("run " + job.string()).exit_code == 0);
  const std::string expected = snapshot(dir / "out");
  // Timed on later clean runs: the first one also warms the page cache (and, in a sanitizer build,
  // is several times slower than the next). The fastest of three: a run slowed by a busy machine
  // would put the kill moments after the end of the runs that are not.
  double clean_s = 1e9;
  for (int k = 0; k < 3; ++k) {
    fs::remove_all(dir / "out");
    fs::remove_all(dir / "cache");
    start = std::chrono::steady_clock::now();
    REQUIRE(run_olt("run " + job.string()).exit_code == 0);
    clean_s = std::min(clean_s, seconds_since(start));
    REQUIRE(snapshot(dir / "out") == expected);
  }

  int killed_midway = 0;
  std::string moments;
  for (int k = 1; k <= 20; ++k) {
    fs::remove_all(dir / "out");
    fs::remove_all(dir / "cache");
    const double at = startup_s + (clean_s - startup_s) * k / 21.0;
    moments += (k > 1 ? ", " : "") + std::to_string(static_cast<int>(at * 1000)) + " ms";
    {
      OltProcess victim({"run", job.string()}, dir / "victim");
      std::this_thread::sleep_for(std::chrono::duration<double>(at));
      const bool killed = victim.stop(SIGKILL, 30) == -1;
      killed_midway += killed;
      // Where it was: the last stage it started, or "start-up", or "publishing".
      const std::string err = victim.err();
      const auto running = err.rfind("): running");
      std::string where = running == std::string::npos
                              ? "start-up"
                              : err.substr(err.rfind("] ", running) + 2,
                                           err.find(' ', err.rfind("] ", running) + 2) - err.rfind("] ", running) - 2);
      if (err.find("report (report): done") != std::string::npos) where = "publishing";
      if (!killed) where = "after the end";
      moments += " (" + where + ")";
    }
    const auto again = run_olt("run " + job.string());
    INFO("killed at " << at << " s; " << again.err);
    REQUIRE(again.exit_code == 0);
    CHECK(snapshot(dir / "out") == expected);
    const auto verify = run_olt("cache verify " + job.string());
    INFO(verify.out);
    CHECK(verify.exit_code == 0);
    CHECK_THAT(verify.out, Catch::Contains("; 0 damaged"));
  }
  INFO("clean run " << clean_s << " s; kill moments " << moments);
  CHECK(killed_midway >= 15);  // most moments fall inside the run (start-up takes part of it)
  WARN("kill test: start-up " << startup_s << " s, clean run " << clean_s << " s; killed at " << moments << "; "
                              << killed_midway << " of 20 kills landed before the run's end");
}
