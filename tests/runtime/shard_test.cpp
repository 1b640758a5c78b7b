// Where a shard comes from: --shard, a Slurm job array's variables, a Kubernetes Indexed Job's.
#include "olt/runtime/shard.h"

#include <catch2/catch.hpp>
#include <map>

#include "olt/core/error.h"

using namespace olt;

namespace {

EnvironmentVariables env_of(std::map<std::string, std::string> vars) {
  auto shared = std::make_shared<std::map<std::string, std::string>>(std::move(vars));
  return [shared](const char* name) -> const char* {
    auto it = shared->find(name);
    return it == shared->end() ? nullptr : it->second.c_str();
  };
}

}  // namespace

TEST_CASE("shard i/N from the command line is parsed and checked") {
  CHECK(parse_shard("0/4") == Shard{0, 4});
  CHECK(parse_shard("3/4") == Shard{3, 4});
  for (const char* bad : {"4/4", "1/0", "-1/4", "a/4", "1", "1/", "/4", "1/4/2", ""}) {
    INFO(bad);
    CHECK_THROWS_WITH(parse_shard(bad), Catch::Contains("expected i/N"));
  }
}

TEST_CASE("a Slurm array task is a shard: (ID - MIN) / STEP of COUNT") {
  CHECK(shard_from_environment(
            env_of({{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_COUNT", "4"}})) ==
        Shard{2, 4});
  CHECK(shard_from_environment(env_of({{"SLURM_ARRAY_TASK_ID", "14"},
                                       {"SLURM_ARRAY_TASK_MIN", "10"},
                                       {"SLURM_ARRAY_TASK_STEP", "2"},
                                       {"SLURM_ARRAY_TASK_COUNT", "3"}})) == Shard{2, 3});
  CHECK_THROWS_WITH(shard_from_environment(env_of({{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_MIN", "0"}})),
                    Catch::Contains("SLURM_ARRAY_TASK_COUNT"));
  CHECK_THROWS_WITH(
      shard_from_environment(
          env_of({{"SLURM_ARRAY_TASK_ID", "5"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_COUNT", "4"}})),
      Catch::Contains("no gaps"));
  CHECK_THROWS_WITH(
      shard_from_environment(
          env_of({{"SLURM_ARRAY_TASK_ID", "x"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_COUNT", "4"}})),
      Catch::Contains("SLURM_ARRAY_TASK_ID"));
}

TEST_CASE("a Kubernetes Indexed Job is a shard when OLT_SHARD_COUNT gives the count") {
  CHECK(shard_from_environment(env_of({{"JOB_COMPLETION_INDEX", "1"}, {"OLT_SHARD_COUNT", "3"}})) == Shard{1, 3});
  CHECK_THROWS_WITH(shard_from_environment(env_of({{"JOB_COMPLETION_INDEX", "1"}})),
                    Catch::Contains("OLT_SHARD_COUNT is not"));
  CHECK_THROWS_WITH(shard_from_environment(env_of({{"OLT_SHARD_COUNT", "3"}})),
                    Catch::Contains("JOB_COMPLETION_INDEX is not"));
  CHECK_FALSE(shard_from_environment(env_of({})).has_value());
}

TEST_CASE("conflicting shard sources are an error and agreeing ones are fine") {
  const auto slurm =
      env_of({{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_COUNT", "4"}});
  CHECK(resolve_shard("1/4", slurm) == Shard{1, 4});
  CHECK_THROWS_WITH(resolve_shard("2/4", slurm), Catch::Contains("the environment says 1/4"));
  CHECK_THROWS_WITH(shard_from_environment(env_of({{"SLURM_ARRAY_TASK_ID", "1"},
                                                   {"SLURM_ARRAY_TASK_MIN", "0"},
                                                   {"SLURM_ARRAY_TASK_COUNT", "4"},
                                                   {"JOB_COMPLETION_INDEX", "2"},
                                                   {"OLT_SHARD_COUNT", "4"}})),
                    Catch::Contains("Slurm array says shard 1/4"));
  CHECK(resolve_shard("", env_of({})) == std::nullopt);
  CHECK(resolve_shard("0/2", env_of({})) == Shard{0, 2});
}
