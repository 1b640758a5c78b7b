#pragma once
// Running a job like ninja, with content instead of mtimes: each stage's cache key is the hash of
// (kind, kind version, canonical params, digests of the artifacts it reads, digests of the files it
// reads). A stage whose key is in the cache is not run; one that runs gets the reason (never run,
// params changed, input X changed, file F changed). Since keys use the *output* digests of inputs,
// a re-run stage whose output is unchanged does not make downstream stages re-run.
#include <atomic>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "olt/cache/store.h"
#include "olt/job/job.h"
#include "olt/runtime/environment.h"
#include "olt/runtime/shard.h"

namespace olt {

struct StageStatus {
  std::string id;
  std::string kind;
  std::string status;                   ///< "cached" or "run" (plan), "cached" or "ran" (run)
  std::string reason;                   ///< why it runs; "unchanged" when cached
  double seconds = 0;                   ///< time spent (run only)
  nlohmann::json summary;               ///< what the stage reported (run only)
  nlohmann::json detail;                ///< what running would do in detail, where the stage kind can tell (plan only)
  std::vector<std::string> unit_names;  ///< stages with units, plan with unit_names: "sensor/observation"
};

struct PlanOptions {
  bool unit_names = false;  ///< name the units of stages with units (runs the source aside if not cached)
  Environment env;
};

struct RunOptions {
  std::optional<Shard> shard;  ///< olt run --shard: only this shard's units, nothing published
  int merge_shards = 0;        ///< olt merge of N shards: stages with units take every unit from the cache
  Environment env;
  /// Once true (a signal's handler sets it), the run ends at the next boundary: no unit (frame) is
  /// started, no stage, no publish, and a wait for another process's lock ends; RunStopped is
  /// thrown. What it stored is kept, and durable.
  const std::atomic<bool>* stop = nullptr;
};

/// A run ended early because RunOptions::stop was set: the output is as it was before the run; the
/// units and stages it finished are in the cache, synced, for the next run to find.
class RunStopped : public std::runtime_error {
 public:
  explicit RunStopped(std::string where) : std::runtime_error("stopped " + where), where_(std::move(where)) {}
  const std::string& where() const { return where_; }  ///< "before publishing", "with 300 of 320 frames ..."

 private:
  std::string where_;
};

/// A stage threw something other than InputError.
class StageFailure : public std::runtime_error {
 public:
  StageFailure(std::string stage, const std::string& message)
      : std::runtime_error("stage '" + stage + "' failed: " + message), stage_(std::move(stage)) {}
  const std::string& stage() const { return stage_; }

 private:
  std::string stage_;
};

/// load_job against the stage kinds this olt runs, with the files each stage reads listed (what its
/// key hashes and `olt watch` watches; throws InputError listing every problem).
Job load_runnable_job(const fs::path& file);

/// What `olt run` would do, without running anything.
std::vector<StageStatus> plan_job(const Job& job, const PlanOptions& options = {});

/// Runs what is needed, then publishes every stage's outputs and OUTPUT/manifest.json. Throws
/// InputError (bad input found while running), StageFailure, or ShardsIncomplete (assemble: frames
/// missing) or RunStopped (options.stop); the output folder is then untouched. With a shard: runs its units (see
/// units.h), publishes nothing, and records the shard as finished in CACHE/shards/ for `olt merge`. Two processes
/// sharing a cache compute a stage once: the second waits for the first's lock (until options.stop).
std::vector<StageStatus> run_job(const Job& job, const RunOptions& options = {});

/// `olt merge`: checks that every shard of the job finished on the job's current inputs (throws
/// ShardsIncomplete naming the missing ones), then runs the job assembling the shards' frames and
/// publishes the output, byte-identical to a run without shards.
/// `stop` as RunOptions::stop.
std::vector<StageStatus> merge_job(const Job& job, const Environment& env = {},
                                   const std::atomic<bool>* stop = nullptr);

/// `olt cache gc`: removes what no job's last run (records/ of every job using the cache)
/// references, holding the cache's gc lock, which every run shares.
Store::Collection collect_cache_garbage(const fs::path& cache);

/// The same, unless another process is using the cache now (a run, another gc): then nothing is
/// removed and nullopt returned. For `olt watch`, which collects while idle and must not wait.
std::optional<Store::Collection> collect_cache_garbage_unless_busy(const fs::path& cache);

}  // namespace olt
