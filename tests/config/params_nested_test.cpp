// Nested parameter tables and old spellings: settings nested in YAML as in their structs, one field
// list serving a flat table and a nested one, and the flat keys of earlier versions still accepted
// (same canonical params, so the same cache keys; errors where the user wrote them).
#include <catch2/catch.hpp>
#include <cmath>

#include "olt/config/params.h"
#include "olt/stages/stage.h"

using namespace olt;

namespace {

struct Solver {
  std::string method = "gicp";
  int max_iterations = 30;
};

struct Settings {
  Solver solver;
  double voxel_m = 0.03;
};

struct Config {
  std::string mode = "a";
  Settings settings;
};

std::shared_ptr<const Params<Config>> table() {
  auto solver = std::make_shared<Params<Solver>>();
  solver->choice("method", &Solver::method, {"gicp", "icp"}, "solver")
      .integer("max_iterations", &Solver::max_iterations, between(1, 100), "iterations");
  auto settings = std::make_shared<Params<Settings>>();
  settings->nested("solver", &Settings::solver, std::shared_ptr<const Params<Solver>>(solver), "the solver")
      .number("voxel_m", &Settings::voxel_m, positive(), "voxel, m");
  auto t = std::make_shared<Params<Config>>();
  t->choice("mode", &Config::mode, {"a", "b"}, "mode")
      .nested("settings", &Config::settings, std::shared_ptr<const Params<Settings>>(settings), "settings")
      .renamed("algorithm", "settings/solver/method")
      .renamed("voxel_m", "settings/voxel_m");
  return t;
}

nlohmann::json canonical(const FieldTable& t, const std::string& yaml, std::vector<Diagnostic>& errors) {
  const Document doc = parse_yaml("job.yaml", yaml);
  return t.canonical(doc, "/params", ".", "stage 's'", errors);
}

std::string messages(const std::vector<Diagnostic>& errors) {
  std::string text;
  for (const auto& e : errors) text += e.str() + "\n";
  return text;
}

}  // namespace

TEST_CASE("nested params: defaults filled at every level, values read into the nested structs") {
  const auto t = table();
  std::vector<Diagnostic> errors;
  const auto params = canonical(*t, "params:\n  settings:\n    solver: {method: icp}\n", errors);
  REQUIRE(errors.empty());
  CHECK(params == nlohmann::json::parse(
                      R"({"mode":"a","settings":{"solver":{"method":"icp","max_iterations":30},"voxel_m":0.03}})"));
  const Config c = t->from_json(params);
  CHECK(c.settings.solver.method == "icp");
  CHECK(c.settings.solver.max_iterations == 30);
  CHECK(t->to_json(c) == params);
}

TEST_CASE("nested params: a bad value deep inside is reported at its line and column, by its path") {
  std::vector<Diagnostic> errors;
  canonical(*table(), "params:\n  settings:\n    solver:\n      max_iterations: 500\n", errors);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].line == 4);
  CHECK(errors[0].column == 23);
  CHECK_THAT(errors[0].message, Catch::Contains("settings: solver: parameter 'max_iterations'"));
  CHECK_THAT(errors[0].message, Catch::Contains("expected in [1, 100], got 500"));
}

TEST_CASE("old spellings give the same canonical params as the new places - their errors point where written") {
  const auto t = table();
  std::vector<Diagnostic> errors;
  const auto old_spelling = canonical(*t, "params:\n  algorithm: icp\n  voxel_m: 0.05\n", errors);
  REQUIRE(errors.empty());
  const auto new_spelling = canonical(*t, "params:\n  settings: {solver: {method: icp}, voxel_m: 0.05}\n", errors);
  REQUIRE(errors.empty());
  CHECK(old_spelling == new_spelling);

  canonical(*t, "params:\n  mode: b\n  voxel_m: -1\n", errors);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].line == 3);
  CHECK(errors[0].column == 12);

  errors.clear();
  canonical(*t, "params:\n  settings: {solver: {method: gicp}}\n  algorithm: icp\n", errors);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].line == 3);
  CHECK_THAT(messages(errors), Catch::Contains("'algorithm' is the old spelling of 'settings.solver.method', and "
                                               "the job gives that place too"));
}

namespace {

// A valid value of `field` other than `current` (its default).
nlohmann::json other_value(const FieldInfo& field, const nlohmann::json& current) {
  if (field.type == FieldType::kChoice)
    for (const auto& choice : field.choices)
      if (choice != current.get<std::string>()) return choice;
  if (field.type == FieldType::kBoolean) return !current.get<bool>();
  const double now = current.get<double>();
  for (double candidate : {now * 0.5, now * 1.5, now + 1, now - 1, now + 0.01}) {
    if (field.type == FieldType::kInteger) candidate = std::round(candidate);
    const bool above = field.exclusive_min ? candidate > field.min : candidate >= field.min;
    if (candidate != now && above && candidate <= field.max)
      return field.type == FieldType::kInteger ? nlohmann::json(static_cast<int>(candidate))
                                               : nlohmann::json(candidate);
  }
  FAIL("no other value for " << field.key);
  return current;
}

}  // namespace

TEST_CASE("every old spelling of every stage kind names a field and lands at its new place") {
  int checked = 0;
  for (const auto& kind : stage_kinds()) {
    const FieldTable& t = *kind.spec.params;
    for (const auto& r : t.renamed()) {
      INFO(kind.spec.name << ": " << r.old_key << " -> " << r.path);
      const FieldInfo* field = t.find(r.path);
      REQUIRE(field);
      const nlohmann::json::json_pointer at("/" + r.path);
      const nlohmann::json value = other_value(*field, t.defaults().at(at));
      nlohmann::json nested = nlohmann::json::object();
      nested[at] = value;
      std::vector<Diagnostic> errors;
      const auto old_spelling = canonical(t, "params: " + nlohmann::json{{r.old_key, value}}.dump() + "\n", errors);
      const auto new_spelling = canonical(t, "params: " + nested.dump() + "\n", errors);
      CHECK(messages(errors).empty());
      CHECK(old_spelling == new_spelling);
      CHECK(old_spelling.at(at) == value);
      CHECK(old_spelling != t.defaults());
      ++checked;
    }
  }
  CHECK(checked >= 45);  // poses' flat registration, consistency and laser keys; laser_map's matching keys
}

TEST_CASE("a nested setting written at the top is unknown there, and the message names its place") {
  std::vector<Diagnostic> errors;
  canonical(*table(), "params:\n  max_iterations: 5\n", errors);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].line == 2);
  CHECK_THAT(errors[0].message, Catch::Contains("unknown parameter 'max_iterations'; did you mean "
                                                "'settings.solver.max_iterations'?"));
}
