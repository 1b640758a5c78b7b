// The command line as people type it: a misspelt command gets a guess, -V and --version the
// version, -q/--quiet and -v/--verbose go anywhere on the line, and `olt plan` on a job never run
// says so for every stage; olt watch checks its numbers before it watches.
#include <catch2/catch.hpp>

#include "support/temp_dir.h"
#include "support/tiny_recording.h"

using namespace olt::test;

namespace {

const char* kJob =
    "version: 1\noutput: out\ncache: cache\nstages:\n"
    "  source: {kind: source, params: {format: synthetic, frames: 2, width: 64, height: 48}}\n"
    "  calibrate: {kind: calibrate, needs: [source]}\n"
    "  poses: {kind: poses, needs: [calibrate]}\n";

}  // namespace

TEST_CASE("a misspelt command gets a guess - -V and --version print the version") {
  const auto misspelt = run_olt("runn job.yaml");
  CHECK(misspelt.exit_code == 2);
  CHECK_THAT(misspelt.err, Catch::Contains("unknown command 'runn'; did you mean 'run'?"));
  for (const char* flag : {"-V", "--version"}) {
    const auto version = run_olt(flag);
    INFO(flag);
    CHECK(version.exit_code == 0);
    CHECK_THAT(version.out, Catch::StartsWith("olt "));
  }
}

TEST_CASE("quiet and verbose: -q after the job silences the progress lines, -v is accepted anywhere") {
  TempDir dir;
  write_text(dir / "job.yaml", kJob);
  const auto quiet = run_olt("run " + (dir / "job.yaml").string() + " -q");
  INFO(quiet.err);
  CHECK(quiet.exit_code == 0);
  CHECK(quiet.err.find(" info ") == std::string::npos);
  const auto verbose = run_olt("-v run " + (dir / "job.yaml").string());
  CHECK(verbose.exit_code == 0);
  CHECK_THAT(verbose.err, Catch::Contains(" info ") && Catch::Contains("3 stages: 0 ran, 3 cached"));
}

TEST_CASE("olt plan on a job never run says never run for every stage") {
  TempDir dir;
  write_text(dir / "job.yaml", kJob);
  const Plan plan = plan_of(dir / "job.yaml");
  REQUIRE(plan.reason.size() == 3);
  for (const auto& [stage, reason] : plan.reason) {
    INFO(stage);
    CHECK(reason == "never run");
  }
}

// The run's last lines: where the output and the report are, then the warnings again, from a
// cached run too (where they are read).
TEST_CASE("the run's last lines name the report and repeat the warnings, cached or not") {
  TempDir dir;
  const std::string job = std::string(kTinyTumJob) + "  report: {kind: report, needs: [labels, scene]}\n";
  const std::string behind = R"({"version": 1, "boxes": [{"id": "b1", "label": "thing", "center": [0, 0, -2],)"
                             R"( "size": [0.5, 0.5, 0.5], "rotation": [0, 0, 0, 1]}]})";
  for (int run = 0; run < 2; ++run) {
    const std::string log = run_tiny_tum_job(dir.path(), job, behind);
    INFO(log);
    const auto end = log.find(" stages: ");
    REQUIRE(end != std::string::npos);
    const std::string last = log.substr(end);
    CHECK_THAT(last, Catch::Contains("; report: " + (dir / "out/report/index.html").string()));
    CHECK_THAT(last, Catch::Contains("labels: box 'b1' (thing): no frame sees it"));
  }
}

TEST_CASE("each stage's log line is one plain sentence of what it made, cached or not") {
  TempDir dir;
  write_text(dir / "job.yaml", kJob);
  for (const char* status : {"done in ", "cached: "}) {
    const auto run = run_olt("run " + (dir / "job.yaml").string());
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    for (const auto& [stage, sentence] : {std::pair{"source (source): ", "read 2 RGB-D observations"},
                                          {"calibrate (calibrate): ", "calibrated 1 sensor"},
                                          {"poses (poses): ", "posed 2 observations"}}) {
      const auto at = run.err.rfind(stage);  // the stage's last line: done or cached
      REQUIRE(at != std::string::npos);
      const std::string line = run.err.substr(at, run.err.find('\n', at) - at);
      CHECK_THAT(line, Catch::StartsWith(stage + std::string(status)) && Catch::EndsWith(sentence));
    }
    CHECK(run.err.find('{') == std::string::npos);  // no JSON
  }
}

TEST_CASE("a path that does not exist is said once, naming it, with no other message about it") {
  TempDir dir;
  write_text(dir / "job.yaml",
             "version: 1\noutput: out\nstages:\n"
             "  source: {kind: source, params: {format: tum, path: data/my_rom, sensor: kinect}}\n");
  const auto validate = run_olt("validate " + (dir / "job.yaml").string());
  CHECK(validate.exit_code == 2);
  CHECK_THAT(validate.err, Catch::Contains("job.yaml:4:") &&
                               Catch::Contains("parameter 'path': 'data/my_rom' does not exist (resolved to " +
                                               (dir / "data/my_rom").string() + ")"));
  CHECK_THAT(validate.err, Catch::Contains("(1 problem)") || Catch::Contains("invalid input\n"));
  CHECK(validate.err.find("needs 'path'") == std::string::npos);
}

TEST_CASE("olt watch's numbers are checked before it watches: the flag, what it expected and what it got") {
  TempDir dir;
  write_text(dir / "job.yaml", kJob);
  // An address that cannot be parsed too: were a number let through, the daemon would stop on it
  // (another message, so the check fails) instead of watching for ever.
  const std::string watch = "watch " + (dir / "job.yaml").string() + " --listen=no:such:address ";
  const auto memory = run_olt(watch + "--image-memory=lots");
  CHECK(memory.exit_code == 2);
  CHECK_THAT(memory.err,
             Catch::Contains("--image-memory: expected a whole number of megabytes from 0 to 1000000, got 'lots'"));
  CHECK_THAT(run_olt(watch + "--image-memory=2000000").err, Catch::Contains("got '2000000'"));
  const auto poll = run_olt(watch + "--poll=0");
  CHECK(poll.exit_code == 2);
  CHECK_THAT(poll.err, Catch::Contains("--poll: expected a number of seconds in (0, 3600], got '0'"));
  CHECK_THAT(run_olt(watch + "--gc-idle=-1").err,
             Catch::Contains("--gc-idle: expected a number of seconds in (0, 3600], got '-1'"));
  const auto both = run_olt(watch + "--gc-idle=5 --no-gc");
  CHECK(both.exit_code == 2);
  CHECK_THAT(both.err, Catch::Contains("--gc-idle: --no-gc says never to collect"));
  CHECK(!std::filesystem::exists(dir / "out"));  // nothing ran
}
