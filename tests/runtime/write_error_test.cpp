// A disk that fills up or fails, at any write: a run whose every stage re-runs (an edited job) is
// given ENOSPC at its 1st, 2nd, ... write (olt/core/fault.h: every write, append and copy of a
// file, cache and output alike) until it has no more writes, and EIO at every sixth. Each time the
// run fails with exit 1 and the system's own words naming a file, the output is the previous run's
// byte for byte (publishing is all-or-nothing), `olt cache verify` finds no damaged entry, and the
// next run without the fault publishes exactly what a clean run does. Deterministic: one thread,
// writes counted, no timer.
#include <catch2/catch.hpp>
#include <cstdlib>

#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

// Every stage kind on a tiny synthetic room; `frames` is what the edit changes (so all re-run).
std::string job(int frames) {
  return "version: 1\noutput: out\ncache: cache\nstages:\n"
         "  source: {kind: source, params: {format: synthetic, frames: " +
         std::to_string(frames) +
         ", width: 64, height: 48}}\n"
         "  calibrate: {kind: calibrate, needs: [source]}\n"
         "  poses: {kind: poses, needs: [calibrate]}\n"
         "  scene: {kind: reconstruct, needs: [poses], params: {every: 2}}\n"
         "  annotations: {kind: annotations, needs: [source]}\n"
         "  labels: {kind: propagate, needs: [poses, annotations]}\n"
         "  dataset: {kind: export, needs: [labels]}\n"
         "  report: {kind: report, needs: [labels, scene]}\n";
}

void run_ok(const fs::path& job_file) {
  const auto run = run_olt("run " + job_file.string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
}

// The job's folder as the first run left it: its output and cache.
void restore(const fs::path& saved, const fs::path& work) {
  fs::remove_all(work);
  fs::copy(saved, work, fs::copy_options::recursive);
}

bool leftovers(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().filename().string().rfind(".tmp.", 0) == 0) return true;
  return false;
}

// The edited job run with `error` at its `n`-th write; false where it had fewer writes and finished.
bool failed_at(const fs::path& work, const std::string& error, int n) {
  ::setenv("OLT_FAULT_WRITE_ERROR", (error + ":" + std::to_string(n)).c_str(), 1);
  const auto run = run_olt("run " + (work / "job.yaml").string());
  ::unsetenv("OLT_FAULT_WRITE_ERROR");
  INFO(error << " at write " << n << ": " << run.err);
  if (run.err.find("fault injection") == std::string::npos) {
    CHECK(run.exit_code == 0);
    return false;
  }
  CHECK(run.exit_code == 1);
  CHECK_THAT(run.err, Catch::Contains(error == "ENOSPC" ? "No space left on device" : "Input/output error"));
  CHECK_THAT(run.err, Catch::Contains(work.string()));  // names the file it could not write
  return true;
}

}  // namespace

TEST_CASE("a full or failing disk at any write of a run leaves the old output, a sound cache and a clean next run") {
  TempDir dir;
  ::setenv("OLT_THREADS", "1", 1);  // the writes in one order
  const fs::path work = dir / "work", saved = dir / "saved", clean = dir / "clean";
  write_text(clean / "job.yaml", job(3));
  run_ok(clean / "job.yaml");
  const std::string edited_output = snapshot(clean / "out");
  write_text(work / "job.yaml", job(2));
  run_ok(work / "job.yaml");
  const std::string old_output = snapshot(work / "out");
  REQUIRE(old_output != edited_output);
  fs::copy(work, saved, fs::copy_options::recursive);

  // Under the sanitizers (CI), every tenth case's processes are checked for leaks: this test starts
  // ~500 olt processes, and LeakSanitizer's own tracer dies now and then at a process's exit ("Tracer
  // caught signal 11"; google/sanitizers#1170, no report of ours), often enough over 500 to fail the
  // test. Memory errors stay checked in all of them; leaks on these paths in the sampled tenth.
  const bool had_options = std::getenv("ASAN_OPTIONS") != nullptr;
  const std::string sanitizer_options = had_options ? std::getenv("ASAN_OPTIONS") : "";
  int failures = 0;
  for (const std::string error : {"ENOSPC", "EIO"}) {
    const int step = error == "ENOSPC" ? 1 : 6;
    for (int n = 1; n < 2000; n += step) {
      const bool check_leaks = failures % 10 == 0;
      ::setenv("ASAN_OPTIONS", (sanitizer_options + (check_leaks ? "" : ":detect_leaks=0")).c_str(), 1);
      restore(saved, work);
      write_text(work / "job.yaml", job(3));
      if (!failed_at(work, error, n)) break;
      ++failures;
      INFO(error << " at write " << n);
      CHECK(snapshot(work / "out") == old_output);
      const auto verify = run_olt("cache verify " + (work / "job.yaml").string());
      INFO(verify.out);
      CHECK(verify.exit_code == 0);
      CHECK_THAT(verify.out, Catch::Contains("; 0 damaged"));
      run_ok(work / "job.yaml");
      CHECK(snapshot(work / "out") == edited_output);
      CHECK_FALSE(leftovers(work));
    }
  }
  ::unsetenv("OLT_THREADS");
  if (had_options)
    ::setenv("ASAN_OPTIONS", sanitizer_options.c_str(), 1);
  else
    ::unsetenv("ASAN_OPTIONS");
  CHECK(failures >= 40);  // a run of every stage kind writes well over 30 files
}
