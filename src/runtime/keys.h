#pragma once
// Cache keys: what a stage's result is made of, as a record and its hash (private to the runtime;
// why a stage runs again: explain.h).
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "olt/cache/store.h"
#include "olt/job/job.h"
#include "olt/runtime/environment.h"
#include "olt/stages/stage.h"

namespace olt {

/// Everything that determines a stage's output: {kind, version, params, inputs, files}, and the
/// output folder for kinds that read it; inputs are keyed by artifact kind, so renaming a stage
/// does not invalidate the cache.
nlohmann::json key_record(const Job& job, const StageDecl& stage, const StageKind& kind,
                          const std::map<std::string, std::string>& input_digests, FileDigests& digests);
std::string key_of(const nlohmann::json& record);
/// Identifies the job file in records/ (the hash of its absolute path).
std::string job_id(const Job& job);
/// What a job's results are made of before anything runs: every stage's kind, version, needs,
/// params and the digests of the files it reads. Shards and their merge must agree on it.
std::string job_digest(const Job& job, FileDigests& digests, const Environment& env);

}  // namespace olt
