#pragma once
// Running a job like ninja, with content instead of mtimes: each stage's cache key is the hash of
// (kind, kind version, canonical params, digests of the artifacts it reads, digests of the files it
// reads). A stage whose key is in the cache is not run; one that runs gets the reason (never run,
// params changed, input X changed, file F changed). Since keys use the *output* digests of inputs,
// a re-run stage whose output is unchanged does not make downstream stages re-run.
#include <string>
#include <vector>

#include "olt/job/job.h"

namespace olt {

struct StageStatus {
  std::string id;
  std::string kind;
  std::string status;      ///< "cached" or "run" (plan), "cached" or "ran" (run)
  std::string reason;      ///< why it runs; "unchanged" when cached
  double seconds = 0;      ///< time spent (run only)
  nlohmann::json summary;  ///< what the stage reported (run only)
  nlohmann::json detail;   ///< what running would do in detail, where the stage kind can tell (plan only)
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

/// What `olt run` would do, without running anything.
std::vector<StageStatus> plan_job(const Job& job);

/// Runs what is needed, then publishes every stage's outputs and OUTPUT/manifest.json. Throws
/// InputError (bad input found while running) or StageFailure; the output folder is then untouched.
std::vector<StageStatus> run_job(const Job& job);

}  // namespace olt
