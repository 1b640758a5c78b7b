// The JSON schema in schemas/ and the stage config tables agree (STYLE.md, rule 2).
#include <catch2/catch.hpp>
#include <iostream>

#include "olt/job/schema.h"
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

// Not run by default: `olt_tests "[.generate]"` prints the definitions to paste into the schema.
TEST_CASE("print the params definitions of job.schema.json", "[.generate]") {
  nlohmann::json definitions;
  for (const auto& k : stage_kinds()) definitions["params_" + k.spec.name] = params_schema(*k.spec.params);
  std::cout << definitions.dump(2) << "\n";
}
