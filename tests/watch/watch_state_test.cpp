// The daemon's counters and their two renderings, against hand-written expectations.
#include "olt/watch/watch_state.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"
#include "olt/watch/file_stamps.h"
#include "olt/watch/http_endpoint.h"
#include "support/temp_dir.h"

using namespace olt;

namespace {

StageStatus stage(const std::string& id, const std::string& kind, const std::string& status, double seconds) {
  return {id, kind, status, status == "ran" ? "input changed" : "unchanged", seconds, nullptr, nullptr, {}};
}

}  // namespace

TEST_CASE("watch state counts runs, failures, relabeled frames and stage time") {
  WatchState state;
  WatchCycle first{1,
                   100,
                   2.5,
                   "ok",
                   {},
                   {},
                   {stage("annotations", "annotations", "ran", 0.5), stage("labels", "propagate", "ran", 2.0)},
                   12};
  record_cycle(state, first);
  WatchCycle second{2, 200, 0.25, "invalid_input", {"boxes.json:1:3: expected a value"}, {"boxes.json"}, {}, 0};
  record_cycle(state, second);
  WatchCycle third{3,
                   300,
                   1.0,
                   "ok",
                   {},
                   {"boxes.json"},
                   {stage("annotations", "annotations", "cached", 0), stage("labels", "propagate", "ran", 0.75)},
                   4};
  third.stages[1].summary = {{"warnings", {"box 'b7' (mug): no frame sees it"}}};
  record_cycle(state, third);
  state.image_memory_mb = 64;
  state.image_memory_held = {3 << 20, 7, 2};
  state.freed_pages_held = 512 << 10;

  CHECK(state.runs == 3);
  CHECK(state.failures.at("invalid_input") == 1);
  CHECK(state.frames_relabeled == 16);
  CHECK(state.stage_totals.at("labels").runs == 2);
  CHECK(state.stage_totals.at("labels").seconds_total == Approx(2.75));
  CHECK(state.stage_totals.at("annotations").runs == 1);
  CHECK(state.last_success_unix_s == Approx(301));

  const std::string metrics = metrics_text(state);
  for (const char* line :
       {"olt_watch_runs_total 3\n", "olt_watch_run_failures_total{reason=\"invalid_input\"} 1\n",
        "olt_watch_run_failures_total{reason=\"stage_failed\"} 0\n", "olt_watch_frames_relabeled_total 16\n",
        "olt_watch_stage_runs_total{stage=\"labels\",kind=\"propagate\"} 2\n",
        "olt_watch_stage_duration_seconds_total{stage=\"labels\",kind=\"propagate\"} 2.75\n",
        "olt_watch_stage_last_duration_seconds{stage=\"labels\",kind=\"propagate\"} 0.75\n",
        "olt_watch_last_run_success 1\n", "# TYPE olt_watch_runs_total counter\n",
        "olt_watch_image_memory_bytes 3145728\n", "olt_watch_image_memory_dropped_total 2\n",
        "# TYPE olt_watch_image_memory_bytes gauge\n"})
    CHECK_THAT(metrics, Catch::Contains(line));

  const auto status = status_json(state);
  CHECK(status["runs"] == 3);
  CHECK(status["state"] == "idle");
  CHECK(status["last_run"]["cycle"] == 3);
  CHECK(status["last_run"]["frames_relabeled"] == 4);
  CHECK(status["last_run"]["stages"][1]["status"] == "ran");
  REQUIRE(status["last_run"]["warnings"].size() == 1);
  CHECK(status["last_run"]["warnings"][0] == "labels: box 'b7' (mug): no frame sees it");
  CHECK(status["image_memory"]["mb"] == 64);
  CHECK(status["image_memory"]["held_mb"] == Approx(3.0));
  CHECK(status["image_memory"]["values"] == 7);
  CHECK(status["image_memory"]["dropped"] == 2);
  CHECK(status["image_memory"]["freed_pages_mb"] == Approx(0.5));

  // A cycle a signal stopped is how the daemon ends, not a failure.
  record_cycle(state, WatchCycle{4, 400, 0.5, "stopped", {"stopped in stage 'labels'"}, {"boxes.json"}, {}, 0});
  CHECK(state.runs == 4);
  CHECK(state.failures.size() == 1);
  CHECK(status_json(state)["last_run"]["outcome"] == "stopped");
}

TEST_CASE("prometheus label values are escaped") {
  WatchState state;
  record_cycle(state, WatchCycle{1, 0, 1, "ok", {}, {}, {stage("a\"b\\c", "propagate", "ran", 1)}, 0});
  CHECK_THAT(metrics_text(state), Catch::Contains("stage=\"a\\\"b\\\\c\""));
}

TEST_CASE("listen addresses: port alone is loopback, bad ones are refused naming --listen") {
  CHECK(parse_listen_address("8080").host == "127.0.0.1");
  CHECK(parse_listen_address("8080").port == 8080);
  CHECK(parse_listen_address("0.0.0.0:9").host == "0.0.0.0");
  CHECK(parse_listen_address("[::1]:0").host == "::1");
  CHECK(parse_listen_address("[::1]:0").port == 0);
  CHECK(is_loopback("127.0.0.1"));
  CHECK(is_loopback("::1"));
  CHECK_FALSE(is_loopback("0.0.0.0"));
  for (const char* bad : {"", "localhost:", ":80", "host:99999", "host:8o", "[::1]80"}) {
    INFO(bad);
    CHECK_THROWS_WITH(parse_listen_address(bad), Catch::Contains("--listen"));
  }
}

TEST_CASE("file stamps see a rewrite, a rename into place and a removal") {
  test::TempDir dir;
  const auto file = dir / "boxes.json";
  test::write_text(file, "{}");
  const FileStamps before = stamp_files({file});
  CHECK(changed_files(before, stamp_files({file})).empty());
  test::write_text(dir / "saved.tmp", "{}");  // same size and, maybe, the same mtime: the inode differs
  std::filesystem::rename(dir / "saved.tmp", file);
  CHECK(changed_files(before, stamp_files({file})) == std::vector<std::filesystem::path>{file});
  std::filesystem::remove(file);
  const FileStamps gone = stamp_files({file});
  CHECK_FALSE(gone.at(file).exists);
  CHECK(changed_files(before, gone).size() == 1);
}
