#include "olt/job/job.h"

#include <algorithm>
#include <cstdlib>
#include <set>

#include "graph.h"
#include "olt/config/schema.h"

namespace olt {
namespace {

using nlohmann::json;

const KindSpec* find_kind(const std::vector<KindSpec>& kinds, const std::string& name) {
  for (const auto& k : kinds)
    if (k.name == name) return &k;
  return nullptr;
}

}  // namespace

const StageDecl& Job::stage(const std::string& id) const {
  for (const auto& s : stages)
    if (s.id == id) return s;
  throw std::out_of_range("no stage " + id);
}

std::vector<std::vector<size_t>> stage_steps(const Job& job) {
  std::vector<std::vector<size_t>> steps;
  std::set<std::string> in_step;  // the ids of the last step's stages
  for (size_t i = 0; i < job.stages.size(); ++i) {
    const StageDecl& stage = job.stages[i];
    bool beside = !steps.empty();  // joins the last step
    for (const auto& need : stage.needs) beside = beside && !in_step.count(need);
    for (const auto& input : stage.inputs) beside = beside && !in_step.count(input.second);
    if (!beside) {
      steps.emplace_back();
      in_step.clear();
    }
    steps.back().push_back(i);
    in_step.insert(stage.id);
  }
  return steps;
}

fs::path default_cache_dir(const fs::path& job_dir) {
  if (const char* dir = std::getenv("OLT_CACHE_DIR"); dir && *dir) return fs::path(dir);
  if (const char* dir = std::getenv("XDG_CACHE_HOME"); dir && *dir) return fs::path(dir) / "olt";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "olt";
  return job_dir / ".olt-cache";
}

namespace {

// Reads and checks a job file, collecting every problem before throwing them together.
class JobLoader {
 public:
  JobLoader(const fs::path& file, const std::vector<KindSpec>& kinds) : kinds_(kinds) {
    job_.file = fs::absolute(file).lexically_normal();
    job_.document = load_yaml(file);
    base_ = job_.file.parent_path();
  }

  Job load() {
    const Document& doc = job_.document;
    errors_ = validate_against_schema(doc, "job.schema.json");
    const json& root = doc.value;
    if (!root.is_object()) throw InputError({doc.error_at("", "expected a map with version, output and stages")});
    read_header(root);
    if (root.contains("stages") && root["stages"].is_object())
      for (const auto& [id, body] : root["stages"].items()) read_stage(id, body, root["stages"]);
    check_one_propagate();
    std::vector<std::string> order, cycle;
    if (!topological_order(stages_, order, cycle)) {
      std::string path;
      for (const auto& id : cycle) path += (path.empty() ? "" : " -> ") + id;
      report(doc.error_at(stages_.at(cycle.front()).pointer + "/needs", "cycle in needs: " + path));
    } else {
      for (const auto& id : order) resolve_inputs(stages_.at(id));
    }
    if (!errors_.empty()) {
      std::stable_sort(errors_.begin(), errors_.end(), [](const Diagnostic& a, const Diagnostic& b) {
        return std::tie(a.line, a.column) < std::tie(b.line, b.column);
      });
      throw InputError(errors_);
    }
    for (const auto& id : order) job_.stages.push_back(stages_.at(id));
    return std::move(job_);
  }

 private:
  // Semantic errors are more precise than the schema's at the same place: keep one per position.
  void report(const Diagnostic& d) {
    errors_.erase(std::remove_if(errors_.begin(), errors_.end(),
                                 [&](const Diagnostic& e) {
                                   return e.line == d.line && e.column == d.column &&
                                          e.message.rfind("schema ", 0) == 0;
                                 }),
                  errors_.end());
    errors_.push_back(d);
  }

  // `message`, with "; did you mean 'X'?" where `word` is a likely typo of one of `candidates`.
  static std::string with_guess(std::string message, const std::string& word,
                                const std::vector<std::string>& candidates) {
    const std::string guess = did_you_mean(word, candidates);
    return guess.empty() ? message : message + "; did you mean '" + guess + "'?";
  }

  void check_keys(const json& object, const std::string& pointer, const std::vector<std::string>& known,
                  const std::string& what) {
    for (const auto& [key, unused] : object.items())
      if (!std::count(known.begin(), known.end(), key))
        report(job_.document.error_at_key(pointer + "/" + pointer_escape(key),
                                          with_guess(what + ": unknown key '" + key + "'", key, known)));
  }

  void read_header(const json& root) {
    check_keys(root, "", {"version", "output", "cache", "stages"}, "job");
    if (root.contains("version") && root["version"].is_number_integer()) job_.version = root["version"];
    if (root.contains("output") && root["output"].is_string())
      job_.output = resolve_path(base_, root["output"].get<std::string>());
    job_.cache = root.contains("cache") && root["cache"].is_string()
                     ? resolve_path(base_, root["cache"].get<std::string>())
                     : default_cache_dir(base_);
    // Paths go into JSON records and outputs, which hold UTF-8 only.
    const std::string fix = ": OLT writes paths into JSON, which holds UTF-8 only; rename the folder";
    if (const std::string bad = invalid_utf8(job_.file.string()); !bad.empty())
      report({job_.document.file, 0, 0, "the job's path " + job_.file.string() + " is not UTF-8 (" + bad + ")" + fix});
    else if (const std::string bad_output = invalid_utf8(job_.output.string()); !bad_output.empty())
      report(job_.document.error_at("/output", "the output path is not UTF-8 (" + bad_output + ")" + fix));
    if (const std::string bad = invalid_utf8(job_.cache.string()); !bad.empty() && invalid_utf8(base_.string()).empty())
      report(root.contains("cache")
                 ? job_.document.error_at("/cache", "the cache path is not UTF-8 (" + bad + ")" + fix)
                 : Diagnostic{job_.document.file, 0, 0,
                              "the cache folder " + job_.cache.string() + " (OLT_CACHE_DIR, " +
                                  "XDG_CACHE_HOME or HOME) is not UTF-8 (" + bad + ")" + fix});
  }

  void read_stage(const std::string& id, const json& body, const json& all) {
    const Document& doc = job_.document;
    StageDecl s;
    s.id = id;
    s.pointer = "/stages/" + pointer_escape(id);
    if (!body.is_object()) return;  // the schema reported it
    check_keys(body, s.pointer, {"kind", "needs", "params"}, "stage '" + id + "'");
    if (body.contains("kind") && body["kind"].is_string()) s.kind = body["kind"];
    if (body.contains("needs") && body["needs"].is_array())
      for (const auto& need : body["needs"])
        if (need.is_string()) s.needs.push_back(need);
    if (const KindSpec* kind = find_kind(kinds_, s.kind)) {
      std::vector<Diagnostic> param_errors;
      s.params = body.contains("params") ? kind->params->canonical(doc, s.pointer + "/params", base_,
                                                                   "stage '" + id + "' (" + s.kind + ")", param_errors)
                                         : kind->params->defaults();
      for (const auto& d : param_errors) report(d);
    } else {
      std::vector<std::string> names;
      for (const auto& k : kinds_) names.push_back(k.name);
      report(doc.error_at(s.pointer + "/kind",
                          with_guess("stage '" + id + "': unknown kind '" + s.kind + "'", s.kind, names)));
    }
    std::vector<std::string> ids;
    for (const auto& [other, unused] : all.items()) ids.push_back(other);
    for (size_t i = 0; i < s.needs.size(); ++i)
      if (!all.contains(s.needs[i]))
        report(
            doc.error_at(s.pointer + "/needs/" + std::to_string(i),
                         with_guess("stage '" + id + "': needs '" + s.needs[i] + "', which is not a stage of this job",
                                    s.needs[i], ids)));
    stages_[id] = s;
  }

  // labels.json is written at the output root: one propagate stage per job.
  void check_one_propagate() {
    std::string first;
    for (const auto& [id, s] : stages_) {
      if (s.kind != "propagate") continue;
      if (first.empty())
        first = id;
      else
        report(job_.document.error_at(s.pointer + "/kind", "stage '" + id +
                                                               "': a job has one propagate stage (labels.json is "
                                                               "written at the output root); '" +
                                                               first + "' is one"));
    }
  }

  // Each artifact kind the stage reads, from the one stage of that kind upstream (the one named in
  // needs where several are); then the kind's own checks.
  void resolve_inputs(StageDecl& s) {
    const KindSpec* kind = find_kind(kinds_, s.kind);
    if (!kind) return;
    std::map<std::string, const StageDecl*> upstream;
    const std::vector<std::string> above = ancestors(stages_, s.id);
    for (const auto& wanted : kind->reads) resolve(s, above, wanted, true, upstream);
    for (const auto& wanted : kind->optional_reads) resolve(s, above, wanted, false, upstream);
    if (kind->check) {
      std::vector<Diagnostic> more;
      kind->check(s, upstream, job_.document, more);
      for (const auto& d : more) report(d);
    }
  }

  void resolve(StageDecl& s, const std::vector<std::string>& above, const std::string& wanted, bool required,
               std::map<std::string, const StageDecl*>& upstream) {
    const Document& doc = job_.document;
    std::vector<std::string> candidates;
    for (const auto& a : above)
      if (stages_.at(a).kind == wanted) candidates.push_back(a);
    if (candidates.size() > 1) {
      std::vector<std::string> direct;
      for (const auto& c : candidates)
        if (std::count(s.needs.begin(), s.needs.end(), c)) direct.push_back(c);
      if (direct.size() == 1) candidates = direct;
    }
    if (candidates.size() == 1) {
      s.inputs[wanted] = candidates.front();
      upstream[wanted] = &stages_.at(candidates.front());
    } else if (candidates.size() > 1) {
      std::string list;
      for (const auto& c : candidates) list += (list.empty() ? "" : ", ") + c;
      report(doc.error_at(s.pointer + "/needs", "stage '" + s.id + "': several upstream '" + wanted + "' stages (" +
                                                    list + "); name exactly one in needs"));
    } else if (required) {
      report(doc.error_at_key(doc.values.count(s.pointer + "/needs") ? s.pointer + "/needs" : s.pointer,
                              "stage '" + s.id + "' (" + s.kind + "): needs a '" + wanted +
                                  "' stage upstream (directly or through needs)"));
    }
  }

  const std::vector<KindSpec>& kinds_;
  Job job_;
  fs::path base_;
  std::vector<Diagnostic> errors_;
  std::map<std::string, StageDecl> stages_;
};

}  // namespace

Job load_job(const fs::path& file, const std::vector<KindSpec>& kinds) { return JobLoader(file, kinds).load(); }

}  // namespace olt
