// Parameter tables: enum choices, and `olt help KIND` (every parameter with its doc, what it accepts
// and its default).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "olt/config/params.h"
#include "support/temp_dir.h"

using namespace olt;

namespace {

struct Inner {
  double scale = 1.5;  ///< a number
};

struct Example {
  double weight_m = 0.25;            ///< in [0, 2]
  std::string method = "gicp";       ///< gicp | icp
  std::string file;                  ///< unset by default
  bool keep = false;                 ///< a switch
  std::map<std::string, Inner> per;  ///< nested
};

}  // namespace

TEST_CASE("params help: doc, what each field accepts and its default - nested tables indented") {
  auto inner = std::make_shared<Params<Inner>>();
  inner->number("scale", &Inner::scale, positive(), "scale factor");
  Params<Example> table;
  table.number("weight_m", &Example::weight_m, between(0, 2), "weight, metres")
      .choice("method", &Example::method, {"gicp", "icp"}, "registration method")
      .path("file", &Example::file, true, "input file")
      .boolean("keep", &Example::keep, "keep flagged ones")
      .struct_map("per", &Example::per, std::shared_ptr<const Params<Inner>>(inner), "per sensor");
  CHECK(params_help(table) ==
        "  weight_m: weight, metres\n"
        "      a number in [0, 2]; default 0.25\n"
        "  method: registration method\n"
        "      one of gicp, icp; default \"gicp\"\n"
        "  file: input file\n"
        "      a path (string); not set by default\n"
        "  keep: keep flagged ones\n"
        "      true or false; default false\n"
        "  per: per sensor\n"
        "      a map from names to parameter maps; not set by default\n"
        "      each entry:\n"
        "        scale: scale factor\n"
        "            a number > 0; default 1.5\n");
}

TEST_CASE("olt help KIND prints the stage kind's parameters - an unknown topic gets a suggestion and exit 2") {
  const auto help = test::run_olt("help propagate");
  CHECK(help.exit_code == 0);
  CHECK(help.out.find("stage kind propagate") != std::string::npos);
  CHECK(help.out.find("reads: source, calibrate, poses, annotations") != std::string::npos);
  CHECK(help.out.find("  keep_flagged: also label observations with a flagged pose\n"
                      "      true or false; default false\n") != std::string::npos);
  const auto poses = test::run_olt("help poses");
  CHECK(poses.out.find("  method: how poses are found\n      one of trajectory, registration, laser; default "
                       "\"trajectory\"\n") != std::string::npos);

  const auto typo = test::run_olt("help propgate");
  CHECK(typo.exit_code == 2);
  CHECK(typo.err.find("did you mean 'propagate'?") != std::string::npos);
}

TEST_CASE("an enum choice: jobs, canonical JSON and help speak its names, the code its values") {
  enum class Mode { fast, exact };
  struct WithMode {
    Mode mode = Mode::exact;
  };
  Params<WithMode> table;
  table.choice("mode", &WithMode::mode, Names<Mode>{{"fast", Mode::fast}, {"exact", Mode::exact}}, "how");
  CHECK(table.defaults() == nlohmann::json({{"mode", "exact"}}));
  CHECK(table.from_json({{"mode", "fast"}}).mode == Mode::fast);
  CHECK(table.to_json(WithMode{Mode::fast}) == nlohmann::json({{"mode", "fast"}}));
  CHECK(table.fields().at(0).choices == std::vector<std::string>{"fast", "exact"});
  CHECK(params_help(table) == "  mode: how\n      one of fast, exact; default \"exact\"\n");
  CHECK(name_in(Names<Mode>{{"fast", Mode::fast}}, Mode::exact).empty());
}

// The help and the schema come from one parameter table per kind: every kind the schema knows gets
// its help, and the help names each of the schema's parameters with the schema's own description.
TEST_CASE("olt help KIND for every stage kind lists each parameter of the schema with its description") {
  const auto schema = nlohmann::json::parse(test::read_text(fs::path(OLT_SOURCE_DIR) / "schemas/job.schema.json"));
  int kinds = 0;
  for (const auto& [name, definition] : schema["definitions"].items()) {
    if (name.rfind("params_", 0) != 0) continue;
    const std::string kind = name.substr(7);
    ++kinds;
    const auto help = test::run_olt("help " + kind);
    INFO(kind);
    CHECK(help.exit_code == 0);
    CHECK_THAT(help.out, Catch::StartsWith("stage kind " + kind + " (version "));
    for (const auto& [param, spec] : definition["properties"].items()) {
      const std::string description = spec.value("description", ""), old = "old spelling of ";
      if (description.rfind(old, 0) == 0)  // listed with the old spellings: "NAME = NEW.NAME"
        CHECK_THAT(help.out, Catch::Contains(" " + param + " = " +
                                             description.substr(old.size(), description.find(',') - old.size())));
      else
        CHECK_THAT(help.out, Catch::Contains("\n  " + param + ": " + description));
    }
  }
  CHECK(kinds == 9);
}
