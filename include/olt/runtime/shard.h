#pragma once
// Which part of a job one process runs on a cluster: shard i of N. From `--shard i/N`, or from the
// engine's environment: a Slurm job array (SLURM_ARRAY_TASK_ID, _MIN, _STEP, _COUNT) or a
// Kubernetes Indexed Job (JOB_COMPLETION_INDEX, with the count in OLT_SHARD_COUNT since Kubernetes
// does not pass it). Sources that disagree are an error, not a guess.
#include <functional>
#include <optional>
#include <string>

namespace olt {

struct Shard {
  int index = 0;  ///< 0-based
  int count = 1;
  std::string str() const { return std::to_string(index) + "/" + std::to_string(count); }
  /// Whether the unit at `position` (in the recording's order) is this shard's: every count-th.
  bool owns(size_t position) const { return static_cast<int>(position % static_cast<size_t>(count)) == index; }
  bool operator==(const Shard& o) const { return index == o.index && count == o.count; }
};

/// Parses "i/N" (0 <= i < N <= 100000); throws InputError naming `source`.
Shard parse_shard(const std::string& text, const std::string& source = "--shard");

/// Reads an environment variable (std::getenv, or a map in tests); nullptr when unset.
using EnvironmentVariables = std::function<const char*(const char*)>;

/// The shard the environment names, if any; throws InputError when its variables are incomplete,
/// malformed or contradict each other.
std::optional<Shard> shard_from_environment(const EnvironmentVariables& env);

/// The shard of `olt run`: `flag` ("" when absent) and the environment must agree where both exist.
std::optional<Shard> resolve_shard(const std::string& flag, const EnvironmentVariables& env);

}  // namespace olt
