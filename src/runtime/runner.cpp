#include "olt/runtime/runner.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <set>

#include "artifact_folder.h"
#include "explain.h"
#include "keys.h"
#include "olt/cache/lock.h"
#include "olt/core/error.h"
#include "olt/runtime/publish.h"
#include "olt/runtime/units.h"
#include "olt/stages/stage.h"
#include "shard_records.h"
#include "unit_engine.h"

namespace olt {
namespace {

std::map<std::string, StageInput> stage_inputs(const StageDecl& stage, const std::map<std::string, Artifact>& done) {
  std::map<std::string, StageInput> inputs;
  for (const auto& [kind, id] : stage.inputs) inputs[kind] = {id, done.at(id)};
  return inputs;
}

std::map<std::string, std::string> input_digests(const std::map<std::string, StageInput>& inputs) {
  std::map<std::string, std::string> digests;
  for (const auto& [kind, input] : inputs) digests[kind] = input.artifact.digest;
  return digests;
}

// The stage's artifact from its last run of this job, if still in the cache.
std::optional<Artifact> previous_artifact(const Job& job, const StageDecl& stage, const Store& store) {
  const auto record = store.record(job_id(job), stage.id);
  return record ? store.find(key_of(*record)) : std::nullopt;
}

// What a stage kind's functions read: the job's file, the stage, its inputs and the input files'
// digests.
StageContext stage_context(const Job& job, const StageDecl& stage, const std::map<std::string, StageInput>& inputs,
                           FileDigests& digests) {
  return StageContext{job.file, stage, inputs, [&digests](const fs::path& file) { return digests.digest(file); }};
}

// A stage's failure as the runtime reports it: InputError and ShardsIncomplete as they are, anything
// else as a StageFailure naming the stage.
template <typename F>
void as_stage(const StageDecl& stage, F body) {
  try {
    body();
  } catch (const InputError&) {
    throw;
  } catch (const ShardsIncomplete&) {
    throw;
  } catch (const std::exception& e) {
    throw StageFailure(stage.id, e.what());
  }
}

// What running a stage made: its summary, and what the run did (e.g. units reused), for the log.
struct RunOutcome {
  nlohmann::json summary;
  nlohmann::json report = nlohmann::json::object();
};

// Runs a stage into `out`: its files, publish.json and summary.json; a kind with units has them
// found or run first (when merging N shards, all of them must be in the cache already).
RunOutcome run_into(const StageContext& context, const StageKind& kind, const Store& store, ArtifactFolder& out,
                    int merge_shards = 0) {
  RunOutcome outcome;
  as_stage(context.stage, [&] {
    if (kind.units) {
      const auto work = kind.units(context);
      if (merge_shards > 0) check_units_cached(*work, kind.unit_words, store, context.stage.id, merge_shards);
      UnitsDone done = run_units(*work, kind.unit_words, store, out);
      outcome.report = std::move(done.report);
      outcome.summary = work->assemble(done.entries, context, out);
    } else {
      outcome.summary = kind.run(context, out);
    }
    nlohmann::json published = nlohmann::json::array();
    for (const auto& p : out.published()) published.push_back(to_json(p));
    out.write("publish.json", published.dump(1));
    out.write("summary.json", outcome.summary.dump(1));
  });
  return outcome;
}

// Runs one stage into a fresh artifact folder and commits it; nothing is left behind on failure.
Artifact execute(const StageContext& context, const StageKind& kind, const std::string& key, const Store& store,
                 int merge_shards, nlohmann::json* summary) {
  const fs::path dir = store.begin(key);
  try {
    ArtifactFolder out(dir);
    const RunOutcome outcome = run_into(context, kind, store, out, merge_shards);
    *summary = outcome.summary;
    summary->update(outcome.report);
    return store.commit(key, dir, out.linked(), true, out.references());
  } catch (...) {
    store.discard(dir);
    throw;
  }
}

}  // namespace

Job load_runnable_job(const fs::path& file) { return load_job(file, kind_specs()); }

std::vector<fs::path> stage_files_read(const StageDecl& stage) { return stage_kind(stage.kind).files_read(stage); }

std::vector<StageStatus> plan_job(const Job& job, const PlanOptions& options) {
  const Store store(job.cache);
  FileDigests digests(job.cache / "file-digests.json");
  std::map<std::string, Artifact> done;  // cached, or run aside (light stages) to look further ahead
  std::vector<fs::path> aside;           // folders of the stages run aside, removed at the end
  std::vector<StageStatus> plan;
  try {
    for (const auto& stage : job.stages) {
      StageStatus status{stage.id, stage.kind, "run", "", 0, nullptr, nullptr, {}};
      const StageKind& kind = stage_kind(stage.kind);
      if (options.frame_units && kind.unit_names) {
        const auto source = stage.inputs.find("source");
        if (source != stage.inputs.end() && done.count(source->second))
          status.frame_units = kind.unit_names({source->second, done.at(source->second)});
      }
      std::string pending;
      for (const auto& [input_kind, id] : stage.inputs)
        if (!done.count(id) && pending.empty()) pending = id;
      if (!pending.empty()) {
        status.reason = "input " + pending + " will be re-run";
        plan.push_back(status);
        continue;
      }
      const auto inputs = stage_inputs(stage, done);
      const nlohmann::json record = key_record(stage, kind, input_digests(inputs), digests);
      const std::string key = key_of(record);
      if (auto artifact = store.find(key)) {
        status.status = "cached";
        status.reason = "unchanged";
        done[stage.id] = *artifact;
        plan.push_back(status);
        continue;
      }
      status.reason = rerun_reason(stage, record, store.record(job_id(job), stage.id));
      const StageContext context = stage_context(job, stage, inputs, digests);
      if (kind.units)
        status.detail =
            explain_units(*kind.units(context), kind.unit_words, store, previous_artifact(job, stage, store));
      if (kind.light || (options.frame_units && stage.kind == "source")) {
        const fs::path dir = store.begin(key);
        aside.push_back(dir);
        ArtifactFolder out(dir);
        run_into(context, kind, store, out);
        done[stage.id] = store.describe(key, dir, out.linked());
      }
      plan.push_back(status);
    }
  } catch (...) {
    for (const auto& dir : aside) store.discard(dir);
    throw;
  }
  for (const auto& dir : aside) store.discard(dir);
  digests.save();
  return plan;
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

// A shard's part of a stage with units: its units go into the cache; the stage has no artifact
// until `olt merge` assembles it.
StageStatus run_units_of_shard(const Job& job, const StageDecl& stage, const StageKind& kind,
                               const std::map<std::string, StageInput>& inputs, const Store& store,
                               FileDigests& digests, const Shard& shard) {
  const StageContext context = stage_context(job, stage, inputs, digests);
  nlohmann::json report;
  as_stage(stage, [&] { report = run_shard_units(*kind.units(context), kind.unit_words, store, shard); });
  return {stage.id, stage.kind, "ran", kind.unit_words.unit + "s of shard " + shard.str(), 0, report, nullptr, {}};
}

}  // namespace

std::vector<StageStatus> run_job(const Job& job, const RunOptions& options) {
  const Store store(job.cache);
  const CacheLock no_gc(
      job.cache, "gc", [] { spdlog::info("waiting for olt cache gc to finish"); }, true);
  FileDigests digests(job.cache / "file-digests.json");
  const auto roles = stage_roles(job);
  std::map<std::string, Artifact> done;
  std::vector<StageStatus> report;
  const size_t total = job.stages.size();
  for (const auto& stage : job.stages) {
    const auto start = std::chrono::steady_clock::now();
    const StageKind& kind = stage_kind(stage.kind);
    const std::string counter = "[" + std::to_string(report.size() + 1) + "/" + std::to_string(total) + "] ";
    if (options.shard) {
      const std::string why = not_in_shard(job, roles, stage, *options.shard);
      if (!why.empty()) {
        spdlog::info("{}{} ({}): not in this shard ({})", counter, stage.id, stage.kind, why);
        report.push_back({stage.id, stage.kind, "skipped", why, 0, nullptr, nullptr, {}});
        continue;
      }
    }
    const auto inputs = stage_inputs(stage, done);
    if (options.shard && kind.units) {
      spdlog::info("{}{} ({}): the {}s of shard {}", counter, stage.id, stage.kind, kind.unit_words.unit,
                   options.shard->str());
      StageStatus status = run_units_of_shard(job, stage, kind, inputs, store, digests, *options.shard);
      status.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      spdlog::info("{}{} ({}): done in {:.2f} s: {}", counter, stage.id, stage.kind, status.seconds,
                   status.summary.dump());
      report.push_back(status);
      continue;
    }
    const nlohmann::json record = key_record(stage, kind, input_digests(inputs), digests);
    const std::string key = key_of(record);
    StageStatus status{stage.id, stage.kind, "cached", "unchanged", 0, nullptr, nullptr, {}};
    std::optional<Artifact> artifact = store.find(key);
    std::optional<CacheLock> lock;
    if (!artifact) {
      // Another process sharing the cache (a shard, a person, CI) may be computing the same stage:
      // wait for it rather than compute it twice. Keys are spread over 256 lock files.
      lock.emplace(job.cache, "stage-" + key.substr(0, 2), [&] {
        spdlog::info("{}{} ({}): waiting for another olt process using this cache", counter, stage.id, stage.kind);
      });
      artifact = store.find(key);
    }
    if (artifact) {
      done[stage.id] = *artifact;
      status.summary = nlohmann::json::parse(read_file(artifact->dir / "summary.json"));
      spdlog::info("{}{} ({}): cached", counter, stage.id, stage.kind);
    } else {
      status.status = "ran";
      status.reason = rerun_reason(stage, record, store.record(job_id(job), stage.id));
      spdlog::info("{}{} ({}): running ({})", counter, stage.id, stage.kind, status.reason);
      done[stage.id] =
          execute(stage_context(job, stage, inputs, digests), kind, key, store, options.merge_shards, &status.summary);
      status.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      spdlog::info("{}{} ({}): done in {:.2f} s: {}", counter, stage.id, stage.kind, status.seconds,
                   status.summary.dump());
      store.log({{"job", job.file.string()},
                 {"stage", stage.id},
                 {"key", key},
                 {"reason", status.reason},
                 {"digest", done[stage.id].digest},
                 {"seconds", status.seconds}});
    }
    lock.reset();
    store.save_record(job_id(job), stage.id, record);
    report.push_back(status);
  }
  digests.save();
  if (options.shard) {
    record_finished_shard(job, *options.shard, job_digest(job, digests));
    return report;
  }
  std::vector<std::pair<std::string, Artifact>> artifacts;
  for (const auto& stage : job.stages) artifacts.emplace_back(stage.id, done.at(stage.id));
  publish_outputs(job.output, artifacts);
  return report;
}

Store::Collection collect_cache_garbage(const fs::path& cache) {
  const CacheLock gc(cache, "gc", [] { spdlog::info("waiting for the runs using this cache to finish"); });
  const Store store(cache);
  std::set<std::string> roots;
  for (const auto& record : store.records()) roots.insert(key_of(record));
  return store.collect_garbage(roots);
}

std::vector<StageStatus> merge_job(const Job& job) {
  FileDigests digests(job.cache / "file-digests.json");
  const int count = check_finished_shards(job, job_digest(job, digests));
  spdlog::info("merge: all {} shards of {} finished", count, job.file.string());
  return run_job(job, RunOptions{std::nullopt, count});
}

}  // namespace olt
