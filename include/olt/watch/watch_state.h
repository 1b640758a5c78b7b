#pragma once
// What `olt watch` knows about its runs, and the two ways it tells: GET /status (JSON) and
// GET /metrics (Prometheus text exposition format 0.0.4). Plain data and free functions; the
// daemon guards its one WatchState with a mutex shared with the HTTP threads.
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "olt/core/process_memory.h"
#include "olt/runtime/runner.h"

namespace olt {

/// One cycle: a run of the job after its files changed (or the first run).
struct WatchCycle {
  int number = 0;
  double started_unix_s = 0;
  double seconds = 0;
  std::string outcome;  ///< "ok", "invalid_input" (exit 2 of olt run), "stage_failed" (exit 1), "stopped" (a signal)
  std::vector<std::string> errors;   ///< FILE:LINE:COLUMN: message, or the failure's message
  std::vector<std::string> trigger;  ///< files whose change started the cycle (none for the first)
  std::vector<StageStatus> stages;   ///< as `olt run` reports them; empty when the job did not load
  long frames_relabeled = 0;         ///< observations labeled again (not linked from the cache)
};

struct StageTotals {
  std::string kind;
  long runs = 0;             ///< times the stage ran (not cached)
  double seconds_total = 0;  ///< time spent running it, all cycles
  double last_seconds = 0;   ///< its last run
};

/// What the daemon's cache collections removed (`WatchConfig::gc_idle_s`), all of them.
struct CacheCollections {
  long count = 0;            ///< collections made
  long entries_removed = 0;  ///< cache entries (artifacts, frames, pictures) they removed
  uint64_t bytes_freed = 0;  ///< bytes, with the leftovers of killed runs they removed
  double last_unix_s = 0;    ///< when the last one finished; 0: none yet
};

struct WatchState {
  std::string job;     ///< the job file
  std::string listen;  ///< host:port of the HTTP endpoint, "" without one
  double started_unix_s = 0;
  bool running = false;  ///< a cycle is under way
  size_t watched_files = 0;
  long runs = 0;
  std::map<std::string, long> failures;  ///< by outcome: invalid_input, stage_failed
  long frames_relabeled = 0;
  std::map<std::string, StageTotals> stage_totals;  ///< by stage id
  std::optional<WatchCycle> last;                   ///< the last cycle, good or bad
  double last_success_unix_s = 0;                   ///< 0: none yet
  CacheCollections cache_gc;
  size_t image_memory_mb = 0;    ///< what the daemon keeps between cycles, at most
  std::string image_memory_why;  ///< "--image-memory=64", "an eighth of the machine's 23.5 GB, ..."
  KeptMemory image_memory_held;  ///< what it kept after the last cycle
  size_t freed_pages_held = 0;   ///< bytes of list blocks kept for the next cycle (keep_freed_pages)
};

/// Adds a finished cycle to the state's counters and makes it the last one.
void record_cycle(WatchState& state, WatchCycle cycle);

/// GET /status: {job, state: idle|running, runs, failures, frames_relabeled, last_run: {...},
/// last_success_unix_s, watched_files, cache_gc: {collections, entries_removed, bytes_freed,
/// last_unix_s}, image_memory: {mb, why, held_mb, values, dropped}}.
nlohmann::json status_json(const WatchState& state);

/// GET /metrics: olt_watch_runs_total, olt_watch_run_failures_total{reason},
/// olt_watch_frames_relabeled_total, olt_watch_stage_runs_total{stage,kind},
/// olt_watch_stage_duration_seconds_total{stage,kind}, olt_watch_stage_last_duration_seconds,
/// olt_watch_last_run_success, olt_watch_last_success_timestamp_seconds, olt_watch_running,
/// olt_watch_cache_gc_total, olt_watch_cache_gc_bytes_freed_total, olt_watch_image_memory_bytes,
/// olt_watch_image_memory_dropped_total.
std::string metrics_text(const WatchState& state);

}  // namespace olt
