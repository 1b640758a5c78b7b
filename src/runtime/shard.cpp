#include "olt/runtime/shard.h"

#include "olt/core/error.h"

namespace olt {
namespace {

constexpr int kMaxShards = 100000;

// A non-negative integer, or nullopt when `text` is not one.
std::optional<long> whole_number(const std::string& text) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  return std::stol(text);
}

long env_number(const EnvironmentVariables& env, const char* name, std::optional<long> fallback = std::nullopt) {
  const char* value = env(name);
  if (!value) {
    if (fallback) return *fallback;
    throw InputError(name, "is not set, but the other variables of a Slurm job array are");
  }
  const auto n = whole_number(value);
  if (!n) throw InputError(name, "expected a non-negative integer, got '" + std::string(value) + "'");
  return *n;
}

std::optional<Shard> slurm_shard(const EnvironmentVariables& env) {
  if (!env("SLURM_ARRAY_TASK_ID")) return std::nullopt;
  const long id = env_number(env, "SLURM_ARRAY_TASK_ID"), min = env_number(env, "SLURM_ARRAY_TASK_MIN");
  const long step = env_number(env, "SLURM_ARRAY_TASK_STEP", 1), count = env_number(env, "SLURM_ARRAY_TASK_COUNT");
  if (step == 0 || id < min || (id - min) % step != 0 || (id - min) / step >= count || count > kMaxShards)
    throw InputError("SLURM_ARRAY_TASK_ID", "task " + std::to_string(id) + " is not one of the " +
                                                std::to_string(count) + " tasks from " + std::to_string(min) +
                                                " in steps of " + std::to_string(step) +
                                                " (olt shards need an array of the form --array=M-N[:S] with no gaps)");
  return Shard{static_cast<int>((id - min) / step), static_cast<int>(count)};
}

std::optional<Shard> kubernetes_shard(const EnvironmentVariables& env) {
  const char* index = env("JOB_COMPLETION_INDEX");
  const char* count = env("OLT_SHARD_COUNT");
  if (!index && !count) return std::nullopt;
  if (!index)
    throw InputError("OLT_SHARD_COUNT", "is set but JOB_COMPLETION_INDEX is not (expected both, or --shard i/N)");
  if (!count)
    throw InputError("JOB_COMPLETION_INDEX",
                     "is set but OLT_SHARD_COUNT is not: Kubernetes does not pass the number of completions; "
                     "set OLT_SHARD_COUNT to the Indexed Job's `completions`");
  return parse_shard(std::string(index) + "/" + count, "JOB_COMPLETION_INDEX/OLT_SHARD_COUNT");
}

}  // namespace

Shard parse_shard(const std::string& text, const std::string& source) {
  const auto slash = text.find('/');
  const auto index = slash == std::string::npos ? std::nullopt : whole_number(text.substr(0, slash));
  const auto count = slash == std::string::npos ? std::nullopt : whole_number(text.substr(slash + 1));
  if (!index || !count || *count < 1 || *count > kMaxShards || *index >= *count)
    throw InputError(source, "expected i/N with 0 <= i < N <= " + std::to_string(kMaxShards) + ", got '" + text + "'");
  return Shard{static_cast<int>(*index), static_cast<int>(*count)};
}

std::optional<Shard> shard_from_environment(const EnvironmentVariables& env) {
  const auto slurm = slurm_shard(env);
  const auto kubernetes = kubernetes_shard(env);
  if (slurm && kubernetes && !(*slurm == *kubernetes))
    throw InputError("environment", "the Slurm array says shard " + slurm->str() + ", JOB_COMPLETION_INDEX and " +
                                        "OLT_SHARD_COUNT say " + kubernetes->str());
  return slurm ? slurm : kubernetes;
}

std::optional<Shard> resolve_shard(const std::string& flag, const EnvironmentVariables& env) {
  const auto from_env = shard_from_environment(env);
  if (flag.empty()) return from_env;
  const Shard given = parse_shard(flag);
  if (from_env && !(*from_env == given))
    throw InputError("--shard", "says " + given.str() + " but the environment says " + from_env->str());
  return given;
}

}  // namespace olt
