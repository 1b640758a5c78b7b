// The JSON schema in schemas/ and the stage config tables agree (STYLE.md, rule 2).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "olt/config/schema.h"
#include "olt/stages/stage.h"

using namespace olt;

TEST_CASE("schemas/job.schema.json describes exactly the parameters of every stage kind") {
  const auto& job_schema = schema("job.schema.json");
  std::vector<std::string> kinds = job_schema["definitions"]["stage"]["properties"]["kind"]["enum"];
  std::vector<std::string> names;
  for (const auto& k : stage_kinds()) names.push_back(k.spec.name);
  CHECK(kinds == names);
  for (const auto& k : stage_kinds()) {
    INFO("stage kind " << k.spec.name);
    CHECK(job_schema["definitions"]["params_" + k.spec.name] == params_schema(*k.spec.params));
  }
}

// Not run by default: `olt_tests "[.generate]"` rewrites the stage kinds and params definitions
// of schemas/job.schema.json from the config tables (then rebuild: the schema is compiled in).
TEST_CASE("regenerate the params definitions of job.schema.json", "[.generate]") {
  const std::filesystem::path file = std::filesystem::path(OLT_SOURCE_DIR) / "schemas/job.schema.json";
  nlohmann::json job_schema = nlohmann::json::parse(std::ifstream(file));
  nlohmann::json kinds = nlohmann::json::array(), by_kind = nlohmann::json::array();
  for (const auto& k : stage_kinds()) {
    job_schema["definitions"]["params_" + k.spec.name] = params_schema(*k.spec.params);
    kinds.push_back(k.spec.name);
    by_kind.push_back({{"if", {{"properties", {{"kind", {{"const", k.spec.name}}}}}}},
                       {"then", {{"properties", {{"params", {{"$ref", "#/definitions/params_" + k.spec.name}}}}}}}});
  }
  job_schema["definitions"]["stage"]["properties"]["kind"]["enum"] = kinds;
  job_schema["definitions"]["stage"]["allOf"] = by_kind;
  std::ofstream(file) << job_schema.dump(2) << "\n";
}
