#include "olt/runtime/runner.h"

#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <set>

#include "execute.h"
#include "explain.h"
#include "keys.h"
#include "olt/cache/lock.h"
#include "olt/core/allocator.h"
#include "olt/core/error.h"
#include "olt/core/parallel.h"
#include "olt/core/process_memory.h"
#include "olt/core/run_memory.h"
#include "olt/runtime/publish.h"
#include "olt/runtime/units.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/sentences.h"
#include "olt/stages/stage.h"
#include "shard_records.h"
#include "stage_locks.h"
#include "unit_engine.h"

namespace olt {

namespace {

// What a stage freed, returned to the system so that it does not add to the next stage's peak;
// except where the process keeps memory between runs (`olt watch`): there the next cycle would only
// fault it in again (a page fault per 4 KB touched: 7 % of a one-box cycle on the TUM job).
void return_memory_between_stages() {
  if (!keeping_memory()) return_freed_memory();
}

bool inside(const fs::path& path, const fs::path& folder) {
  const fs::path relative = path.lexically_normal().lexically_relative(folder.lexically_normal());
  return !relative.empty() && *relative.begin() != "..";
}

// The output folder is OLT's to write and clean up: it must be a folder (or nothing yet), not inside
// the cache (check_output_place), and the job file, the cache and every input must lie outside it
// (check_inputs_outside_output: `output: .` would mix outputs with them, and a published file could
// take an input's place).
void check_output_place(const Job& job) {
  const auto refuse = [&](const std::string& problem) {
    throw InputError({job.document.error_at("/output", "output " + job.output.string() + " " + problem)});
  };
  std::error_code ec;
  const fs::file_status status = fs::status(job.output, ec);
  if (fs::exists(status) && !fs::is_directory(status))
    refuse("is a file, not a folder: OLT publishes a folder of outputs there; give a folder's path");
  if (inside(job.output, job.cache))
    refuse("is inside the cache " + job.cache.string() +
           ", which `olt cache gc` cleans up; choose a folder of its own");
}

void check_inputs_outside_output(const Job& job) {
  std::vector<std::pair<fs::path, std::string>> inputs = {{job.file, "the job file"}, {job.cache, "the cache"}};
  for (const auto& stage : job.stages)  // in the job's order: the first stage reading it is named
    for (const auto& file : job.files_read.at(stage.id))
      inputs.push_back({file, "an input of stage '" + stage.id + "'"});
  for (const auto& [path, what] : inputs)
    if (inside(path, job.output))
      throw InputError({job.document.error_at(
          "/output", "output " + job.output.string() + " holds " + what + " (" + path.string() +
                         "): OLT writes and removes files in its output folder; choose a folder of its own")});
}

}  // namespace

Job load_runnable_job(const fs::path& file) {
  Job job = load_job(file, kind_specs());
  check_output_place(job);
  for (const auto& stage : job.stages) job.files_read[stage.id] = stage_kind(stage.kind).files_read(stage);
  check_inputs_outside_output(job);
  return job;
}

namespace {

// Whether shard `shard` runs `stage` (see units.h), and if not, why.
std::string not_in_shard(const Job& job, const std::map<std::string, StageRole>& roles, const StageDecl& stage,
                         const Shard& shard) {
  const StageRole role = roles.at(stage.id);
  if (role == StageRole::after_frames) return "needs every frame: runs in olt merge";
  if (role == StageRole::independent) {
    const int owner = owner_shard(job, roles, stage.id, shard.count);
    if (owner != shard.index) return "runs in shard " + std::to_string(owner) + "/" + std::to_string(shard.count);
  }
  return "";
}

// What a run waits for: the cache's lock `name`, held `shared` with other runs or alone; said once
// ("`said_by`waiting for `what`") where another process holds it.
struct LockWait {
  std::string name;
  bool shared;
  std::string what, said_by;
};

// The lock, once free; RunStopped ("while waiting for ...") if the run was asked to stop while it
// waited (it may have taken the lock just then: what it waited to do is not begun after a signal).
CacheLock wait_for(const LockWait& wait, const fs::path& cache, FileSystem& files, const std::atomic<bool>* stop) {
  static const std::atomic<bool> never{false};  // a run no signal stops (in tests): waits as long as it takes
  bool waited = false;
  std::optional<CacheLock> lock = CacheLock::unless_stopped(
      cache, wait.name,
      [&] {
        waited = true;
        spdlog::info("{}waiting for {}", wait.said_by, wait.what);
      },
      stop ? *stop : never, wait.shared, files);
  if (!lock || (waited && stop && *stop)) throw RunStopped("while waiting for " + wait.what);
  return std::move(*lock);
}

// One run of a cache publishes at a time (the changes of one must not be made between another's).
const LockWait kPublishing{"publish", false, "another run to finish publishing", ""};

// One `olt run`: the stages in order, each found in the cache or run, then the outputs published
// (a shard instead records that it finished).

class JobRunner {
 public:
  JobRunner(const Job& job, const RunOptions& options)
      : job_(job),
        options_(options),
        files_(*options.env.files),
        store_(job.cache, files_),
        digests_(job.cache / "file-digests.json", files_),
        roles_(stage_roles(job, options.env)) {
    for (size_t i = 0; i < job.stages.size(); ++i) {
      place_[job.stages[i].id] = i;
      const StageKind& kind = options.env.kind(job.stages[i].kind);
      for (const auto& [input_kind, id] : job.stages[i].inputs) {
        const auto lookups = kind.looks_up.find(input_kind);
        if (lookups == kind.looks_up.end())
          last_use_[id] = i;
        else
          lookups_[id].emplace_back(i, lookups->second);
      }
    }
  }

  StageStatus run(const StageDecl& stage, const std::string& counter) {
    const auto start = std::chrono::steady_clock::now();
    const StageKind& kind = options_.env.kind(stage.kind);
    if (options_.shard) {
      const std::string why = not_in_shard(job_, roles_, stage, *options_.shard);
      if (!why.empty()) {
        spdlog::info("{}{} ({}): not in this shard ({})", counter, stage.id, stage.kind, why);
        return {stage.id, stage.kind, "skipped", why, 0, nullptr, nullptr, {}};
      }
    }
    const auto inputs = [&] {
      const std::lock_guard<std::mutex> lock(done_mutex_);  // a stage beside it may be adding its own
      return stage_inputs(stage, done_, &shared_reads_);
    }();
    StageStatus status = [&] {
      if (options_.shard && kind.units) {
        spdlog::info("{}{} ({}): the {}s of shard {}", counter, stage.id, stage.kind, kind.unit_words.unit,
                     options_.shard->str());
        return finished(units_of_shard(stage, kind, inputs), start, counter);
      }
      return find_or_run(stage, kind, inputs, counter, start);
    }();
    return status;
  }

  // After a step of the job (stage_steps): the file lists no later stage reads let go.
  void after_step(const std::vector<size_t>& step) {
    for (const size_t i : step) let_go_of_lists(job_.stages[i].id);
  }

  void finish() {
    if (digests_.save()) unsynced_ = true;
    if (options_.shard) {
      make_durable();  // the shard's units before the record that says they are there
      return record_finished_shard(files_, job_, *options_.shard, job_digest(job_, digests_, options_.env));
    }
    shared_reads_.clear();  // the stages are done with them
    return_memory_between_stages();
    std::vector<std::pair<std::string, Artifact>> artifacts;  // the run's last use of them: moved, not copied
    for (const auto& stage : job_.stages) artifacts.emplace_back(stage.id, std::move(done_.at(stage.id)));
    try {
      const CacheLock publishing = wait_for(kPublishing, job_.cache, files_, options_.stop);
      // The cache made durable with the changes published, where there are any: one sync for both
      // (the cache first, alone, where the output's files are clones of its own).
      SyncAlong cache;
      if (unsynced_) cache = {{job_.cache}, [this] { synced(); }};
      publish_outputs(
          job_.output, std::move(artifacts), files_, output_listing(job_.cache, job_.output),
          [this](const std::string& stage, const Artifact& artifact) { return files_of(stage, artifact); }, cache);
    } catch (const DamagedArtifact& e) {
      store_.drop(e.key());
      throw StageFailure(e.stage(), std::string(e.what()) + "; the entry was removed from the cache: run again");
    }
    make_durable();
  }

  // What this run wrote into the cache (entries, records) made durable: one sync at the end of a
  // run, rather than one per stage (each waits for every dirty byte of its file system, anyone's).
  // Until then an entry is in place but could be cut short by a power loss, which `Store::find`
  // sees as a file of another size: the entry is made again (docs/robustness.md).
  void make_durable() {
    if (!unsynced_) return;
    try {
      files_.sync({job_.cache});
    } catch (const SyncFailed&) {
      forget_unsynced();
      throw;
    }
    synced();
  }

  // What this run stored is durable.
  void synced() {
    store_.clear_committed();
    unsynced_ = false;
  }

  // After a sync that failed (here or publishing): the entries stored since the last one that
  // worked may not be on the disk as they read now, so they go; the next run makes them again. A
  // sync tried again would not say: a write-back error is told once.
  void forget_unsynced() {
    for (const std::string& key : store_.take_committed()) {
      try {
        store_.remove(key);
      } catch (const std::exception& e) {
        spdlog::warn("{}: cannot remove the entry {} the failed sync may have spoiled: {}", job_.cache.string(), key,
                     e.what());
      }
    }
    unsynced_ = false;
  }

 private:
  // The stage's artifact from the cache, or made now; waits for another process making it.
  StageStatus find_or_run(const StageDecl& stage, const StageKind& kind,
                          const std::map<std::string, StageInput>& inputs, const std::string& counter,
                          std::chrono::steady_clock::time_point start) {
    const nlohmann::json record = key_record(job_, stage, kind, input_digests(inputs), digests_);
    const std::string key = key_of(record);
    StageStatus status{stage.id, stage.kind, "cached", "unchanged", 0, nullptr, nullptr, {}};
    std::optional<Artifact> artifact = store_.find(key);
    StageLock lock;
    if (!artifact) {
      // Another process sharing the cache (a shard, a person, CI) may be computing the same stage:
      // wait for it rather than compute it twice. Keys are spread over 256 lock files, which the
      // stages of this run share (StageLocks).
      const LockWait making{"stage-" + key.substr(0, 2), false, "another olt process using this cache",
                            counter + stage.id + " (" + stage.kind + "): "};
      lock = stage_locks_.hold(
          making.name, key,
          [&]() -> std::shared_ptr<void> {
            return std::make_shared<CacheLock>(wait_for(making, job_.cache, files_, options_.stop));
          },
          [&] { spdlog::info("{}waiting for a stage beside it that makes the same", making.said_by); });
      artifact = store_.find(key);
    }
    if (artifact) {
      done(stage.id, *artifact);
      status.summary = nlohmann::json::parse(store_.files().read(artifact->path("summary.json")));
      spdlog::info("{}{} ({}): cached: {}", counter, stage.id, stage.kind, stage_sentence(stage.kind, status.summary));
    } else {
      status.status = "ran";
      status.reason = rerun_reason(stage, record, store_.record(job_id(job_), stage.id));
      spdlog::info("{}{} ({}): running ({})", counter, stage.id, stage.kind, status.reason);
      const StageContext context = stage_context(job_, stage, inputs, digests_, &store_, &kind);
      unsynced_ = true;  // from the first entry or piece it commits
      Artifact made = execute(context, kind, key, store_, options_.merge_shards, &status.summary, options_.stop);
      const std::string digest = made.digest;
      done(stage.id, std::move(made), true);
      status = finished(std::move(status), start, counter);
      store_.log({{"job", job_.file.string()},
                  {"stage", stage.id},
                  {"key", key},
                  {"reason", status.reason},
                  {"digest", digest},
                  {"seconds", status.seconds}});
    }
    lock = StageLock();
    if (store_.save_record(job_id(job_), stage.id, record)) unsynced_ = true;
    return status;
  }

  // The stage's artifact, found or (`made`) made by this run, for the stages after it.
  void done(const std::string& stage, Artifact artifact, bool made = false) {
    const std::lock_guard<std::mutex> lock(done_mutex_);
    done_[stage] = std::move(artifact);
    if (made) made_.insert(stage);
  }

  // The file lists of the artifacts this run made that no stage after `stage` reads whole (its own,
  // if none does), let go, but for the files a later stage looks up (StageKind::looks_up): the
  // labeling stage's lists 70,000 files at 10,000 observations, and the export's 20,000; the scene
  // after them reads neither, and the report looks up the labeling stage's overlays (10,000).
  // Publishing reads the lists again (files_of) where it needs them. Whole lists are kept after the
  // last stage (publishing, next, needs them); not the lists of artifacts found in the cache (a run
  // that finds them does little else, and would only read them twice); not where the process keeps
  // memory between runs (`olt watch`: there a list read again is a copy of the one it remembers).
  void let_go_of_lists(const std::string& stage) {
    const size_t now = place_.at(stage);
    const bool last = now + 1 == job_.stages.size();
    if (keeping_memory()) return;
    for (const std::string& id : made_) {
      Artifact& artifact = done_.at(id);
      const auto read_whole = last_use_.find(id);
      if (artifact.files.empty() || (read_whole != last_use_.end() && read_whole->second > now)) continue;
      if (last && !in_part_.count(id)) continue;
      std::vector<FileFilter> later;  // what the stages after this one look up
      if (const auto lookups = lookups_.find(id); lookups != lookups_.end())
        for (const auto& [place, keep] : lookups->second)
          if (place > now) later.push_back(keep);
      if (later.empty() || last) {
        artifact.files = ArtifactFiles();
      } else if (in_part_.insert(id).second) {
        artifact.files = artifact.files.only([&](const ListedFile& f) {
          return std::any_of(later.begin(), later.end(), [&](const FileFilter& keep) { return keep(f); });
        });
      }
    }
  }

  // The file list of the stage's artifact, read again from the cache for publishing (after it was let
  // go): as the entry lists them, its files not looked for again (this run made them; publishing
  // hashes what it copies, and names the stage of a file gone meanwhile).
  ArtifactFiles files_of(const std::string& stage, const Artifact& artifact) const {
    std::optional<Artifact> found = store_.find_unchecked(artifact.key);
    if (!found)
      throw StageFailure(stage, "its cache entry " + artifact.key +
                                    " was removed during the run (by hand, or a disk fault): run again");
    if (found->digest != artifact.digest) {  // another entry under its key: not to be found next time
      store_.drop(artifact.key);
      throw StageFailure(stage, "its cache entry " + artifact.key +
                                    " was changed during the run (by hand, or a disk fault); the entry was removed "
                                    "from the cache: run again");
    }
    return std::move(found->files);
  }

  // A shard's part of a stage with units: its units go into the cache; the stage has no artifact
  // until `olt merge` assembles it.
  StageStatus units_of_shard(const StageDecl& stage, const StageKind& kind,
                             const std::map<std::string, StageInput>& inputs) {
    const StageContext context = stage_context(job_, stage, inputs, digests_, &store_, &kind);
    nlohmann::json report;
    unsynced_ = true;  // from the first unit it commits
    as_stage(stage, [&] {
      report = run_shard_units(*kind.units(context), kind.unit_words, store_, *options_.shard, options_.stop);
    });
    return {stage.id, stage.kind, "ran",   kind.unit_words.unit + "s of shard " + options_.shard->str(),
            0,        report,     nullptr, {}};
  }

  static StageStatus finished(StageStatus status, std::chrono::steady_clock::time_point start,
                              const std::string& counter) {
    status.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return_memory_between_stages();
    spdlog::info("{}{} ({}): done in {:.2f} s: {}", counter, status.id, status.kind, status.seconds,
                 stage_sentence(status.kind, status.summary));
    struct rusage usage {};
    if (::getrusage(RUSAGE_SELF, &usage) == 0)
      spdlog::debug("{}{}: peak memory of the run so far {} MB", counter, status.id, usage.ru_maxrss / 1024);
    return status;
  }

  const Job& job_;
  const RunOptions& options_;
  FileSystem& files_;
  const Store store_;
  FileDigests digests_;
  const std::map<std::string, StageRole> roles_;
  std::mutex done_mutex_;  // stages side by side add to the two below
  std::map<std::string, Artifact> done_;
  std::map<std::string, size_t> place_;     // a stage's id -> its place in the job's stages
  std::map<std::string, size_t> last_use_;  // ... -> the place of the last stage that reads it
  std::set<std::string> made_;              // the stages this run ran (not found in the cache)
  std::set<std::string> in_part_;           // ... whose lists it holds only in part
  std::atomic<bool> unsynced_{false};       // whether it wrote into the cache since it last synced
  // An artifact's id -> the stages that look up some of its files (their places) and which.
  std::map<std::string, std::vector<std::pair<size_t, FileFilter>>> lookups_;
  SharedReads shared_reads_;  // the recording and poses the stages read, parsed once: gone with the run
  StageLocks stage_locks_;    // the stage locks this run holds, shared by its stages side by side
};

// The job's stages in steps (stage_steps), where the process keeps memory between runs (`olt watch`):
// there a cycle's time is what an annotator waits for, and the daemon holds its memory anyway.
// Elsewhere one stage a step: a run's peak is then one stage's at a time, which is what a cluster
// job's memory request is sized by (side by side, a 10,000-observation run's peak grew from 70 to 82
// MB, the export's per-frame lists held beside the scene's fusion).
std::vector<std::vector<size_t>> steps_to_run(const Job& job) {
  if (keeping_memory()) return stage_steps(job);
  std::vector<std::vector<size_t>> steps;
  for (size_t i = 0; i < job.stages.size(); ++i) steps.push_back({i});
  return steps;
}

// A stage run beside the one whose failure ends the run failed too: said here, as a run ends with
// one failure (what() names the stage where the stage itself did not: a StageFailure).
void log_also_failed(const std::exception_ptr& failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const std::exception& e) {
    spdlog::error("a stage run beside another failed too: {}", e.what());
  } catch (...) {
    spdlog::error("a stage run beside another failed too");
  }
}

// What a run keeps of the files it writes (run_memory.h): for that run only, let go however it ends.
struct RunMemoryScope {
  RunMemoryScope() { forget_run_memory(); }
  ~RunMemoryScope() { forget_run_memory(); }
  RunMemoryScope(const RunMemoryScope&) = delete;
  RunMemoryScope& operator=(const RunMemoryScope&) = delete;
};

}  // namespace

std::vector<StageStatus> run_job(const Job& job, const RunOptions& options) {
  const CacheLock no_gc =
      wait_for({"gc", true, "olt cache gc to finish", ""}, job.cache, *options.env.files, options.stop);
  const RunMemoryScope run_memory;
  JobRunner runner(job, options);
  Store(job.cache, *options.env.files).mark();
  // What killed runs of this machine left half-made in the cache goes first.
  remove_orphaned_temps(*options.env.files, job.cache / "tmp");
  remove_orphaned_temps(*options.env.files, job.cache / "outputs");
  if (!options.shard) {  // a publish killed after it staged its changes is finished first
    const CacheLock publishing = wait_for(kPublishing, job.cache, *options.env.files, options.stop);
    finish_publishing(job.output, *options.env.files);
  }
  std::vector<StageStatus> report;
  const auto stopped = [&] { return options.stop && *options.stop; };
  const auto run_stage = [&](size_t i) {
    const StageDecl& stage = job.stages[i];
    const std::string counter = "[" + std::to_string(i + 1) + "/" + std::to_string(job.stages.size()) + "] ";
    try {
      return runner.run(stage, counter);
    } catch (const RunStopped& e) {
      throw RunStopped("in stage '" + stage.id + "' (" + stage.kind + ") " + e.where());
    }
  };
  try {
    for (const std::vector<size_t>& step : steps_to_run(job)) {
      const StageDecl& first = job.stages[step.front()];
      if (stopped()) throw RunStopped("before stage '" + first.id + "' (" + first.kind + ")");
      if (step.size() == 1) {
        report.push_back(run_stage(step.front()));
      } else {  // side by side: each ends (into the cache) before the first failure, in the job's order, is told
        std::vector<std::optional<StageStatus>> statuses(step.size());
        std::vector<std::function<void()>> work;
        for (size_t k = 0; k < step.size(); ++k) work.emplace_back([&, k] { statuses[k] = run_stage(step[k]); });
        const std::vector<std::exception_ptr> failures = run_side_by_side(work);
        const auto failed = std::find_if(failures.begin(), failures.end(), [](const auto& f) { return f != nullptr; });
        if (failed != failures.end()) {
          for (auto other = failed + 1; other != failures.end(); ++other)
            if (*other) log_also_failed(*other);
          std::rethrow_exception(*failed);
        }
        for (auto& status : statuses) report.push_back(std::move(*status));
      }
      runner.after_step(step);
    }
    if (stopped()) throw RunStopped(options.shard ? "before recording the shard finished" : "before publishing");
    runner.finish();
  } catch (const SyncFailed&) {
    runner.forget_unsynced();
    throw;
  } catch (...) {
    try {  // what the failed or stopped run stored is kept for the next: durable as a finished run's
      runner.make_durable();
    } catch (const std::exception& e) {
      spdlog::warn("{}: not synced after the run ended early: {}", job.cache.string(), e.what());
    }
    throw;
  }
  return report;
}

namespace {

Store::Collection collect_unreferenced(const fs::path& cache) {
  const Store store(cache);
  std::set<std::string> roots;
  for (const auto& record : store.records()) roots.insert(key_of(record));
  return store.collect_garbage(roots);
}

}  // namespace

Store::Collection collect_cache_garbage(const fs::path& cache) {
  const CacheLock gc(cache, "gc", [] { spdlog::info("waiting for the runs using this cache to finish"); });
  return collect_unreferenced(cache);
}

std::optional<Store::Collection> collect_cache_garbage_unless_busy(const fs::path& cache) {
  const std::optional<CacheLock> gc = CacheLock::if_free(cache, "gc");
  if (!gc) return std::nullopt;
  return collect_unreferenced(cache);
}

std::vector<StageStatus> merge_job(const Job& job, const Environment& env, const std::atomic<bool>* stop) {
  FileDigests digests(job.cache / "file-digests.json", *env.files);
  const int count = check_finished_shards(*env.files, job, job_digest(job, digests, env));
  spdlog::info("merge: all {} shards of {} finished", count, job.file.string());
  RunOptions options;
  options.merge_shards = count;
  options.env = env;
  options.stop = stop;
  return run_job(job, options);
}

}  // namespace olt
