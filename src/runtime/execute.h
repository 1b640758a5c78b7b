#pragma once
// Running one stage (private to the runtime): its inputs from the artifacts done so far, what its
// functions read, and its run into a fresh artifact folder of the store, committed whole or not at
// all. Shared by `olt run`, `olt merge` and `olt plan` (which runs light stages aside).
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "artifact_folder.h"
#include "olt/cache/store.h"
#include "olt/core/error.h"
#include "olt/job/job.h"
#include "olt/runtime/runner.h"
#include "olt/stages/stage.h"

namespace olt {

/// The stage's inputs, from the artifacts of the stages done; `shared`: where they share what they read.
std::map<std::string, StageInput> stage_inputs(const StageDecl& stage, const std::map<std::string, Artifact>& done,
                                               SharedReads* shared = nullptr);
std::map<std::string, std::string> input_digests(const std::map<std::string, StageInput>& inputs);

/// The stage's artifact from its last run of this job, if still in the cache.
std::optional<Artifact> previous_artifact(const Job& job, const StageDecl& stage, const Store& store);

/// What a stage kind's functions read: the job's file, the stage, its inputs and the input files'
/// digests (`digests` must outlive the context); with `store` and the stage's `kind`, the pieces it
/// remembers go to the cache (else they are made every time).
StageContext stage_context(const Job& job, const StageDecl& stage, const std::map<std::string, StageInput>& inputs,
                           FileDigests& digests, const Store* store = nullptr, const StageKind* kind = nullptr);

/// A stage's failure as the runtime reports it: InputError, ShardsIncomplete and RunStopped (not a
/// failure: asked for) as they are, anything else as a StageFailure naming the stage.
template <typename F>
void as_stage(const StageDecl& stage, F body) {
  try {
    body();
  } catch (const InputError&) {
    throw;
  } catch (const ShardsIncomplete&) {
    throw;
  } catch (const RunStopped&) {
    throw;
  } catch (const std::exception& e) {
    throw StageFailure(stage.id, e.what());
  }
}

/// What running a stage made: its summary, and what the run did (e.g. units reused), for the log.
struct RunOutcome {
  nlohmann::json summary;
  nlohmann::json report = nlohmann::json::object();
};

/// Runs a stage into `out`: its files, publish.json and summary.json; a kind with units has them
/// found or run first (when merging N shards, all of them must be in the cache already).
RunOutcome run_into(const StageContext& context, const StageKind& kind, const Store& store, ArtifactFolder& out,
                    int merge_shards = 0, const std::atomic<bool>* stop = nullptr);

/// Runs one stage into a fresh artifact folder and commits it under `key`; nothing is left behind
/// on failure. `summary` gets the stage's summary and the run's report.
Artifact execute(const StageContext& context, const StageKind& kind, const std::string& key, const Store& store,
                 int merge_shards, nlohmann::json* summary, const std::atomic<bool>* stop = nullptr);

}  // namespace olt
