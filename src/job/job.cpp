#include "olt/job/job.h"

#include <algorithm>
#include <cstdlib>
#include <set>

#include "olt/config/schema.h"

namespace olt {
namespace {

using nlohmann::json;

const KindSpec* find_kind(const std::vector<KindSpec>& kinds, const std::string& name) {
  for (const auto& k : kinds)
    if (k.name == name) return &k;
  return nullptr;
}

// Kahn's algorithm; ties by id so the order is stable. Returns false (with the cycle) on a cycle.
bool topological_order(const std::map<std::string, StageDecl>& stages, std::vector<std::string>& order,
                       std::vector<std::string>& cycle) {
  std::map<std::string, int> missing;
  for (const auto& [id, s] : stages) {
    int n = 0;
    for (const auto& need : s.needs) n += stages.count(need) ? 1 : 0;
    missing[id] = n;
  }
  std::set<std::string> ready;
  for (const auto& [id, n] : missing)
    if (n == 0) ready.insert(id);
  while (!ready.empty()) {
    const std::string id = *ready.begin();
    ready.erase(ready.begin());
    order.push_back(id);
    for (const auto& [other, s] : stages)
      if (std::count(s.needs.begin(), s.needs.end(), id) && --missing[other] == 0) ready.insert(other);
  }
  if (order.size() == stages.size()) return true;
  // Walk needs from a stage left over until a stage repeats: that is a cycle.
  std::string at;
  for (const auto& [id, n] : missing)
    if (n > 0) {
      at = id;
      break;
    }
  std::vector<std::string> path;
  while (std::find(path.begin(), path.end(), at) == path.end()) {
    path.push_back(at);
    for (const auto& need : stages.at(at).needs)
      if (stages.count(need) && missing[need] > 0) {
        at = need;
        break;
      }
  }
  cycle.assign(std::find(path.begin(), path.end(), at), path.end());
  cycle.push_back(at);
  return false;
}

// All stages reachable through `needs` from `id`, nearest first.
std::vector<std::string> ancestors(const std::map<std::string, StageDecl>& stages, const std::string& id) {
  std::vector<std::string> found;
  std::vector<std::string> frontier = {id};
  while (!frontier.empty()) {
    std::vector<std::string> next;
    for (const auto& s : frontier)
      for (const auto& need : stages.at(s).needs)
        if (stages.count(need) && std::find(found.begin(), found.end(), need) == found.end()) {
          found.push_back(need);
          next.push_back(need);
        }
    frontier = next;
  }
  return found;
}

}  // namespace

const StageDecl& Job::stage(const std::string& id) const {
  for (const auto& s : stages)
    if (s.id == id) return s;
  throw std::out_of_range("no stage " + id);
}

fs::path default_cache_dir(const fs::path& job_dir) {
  if (const char* dir = std::getenv("OLT_CACHE_DIR"); dir && *dir) return fs::path(dir);
  if (const char* dir = std::getenv("XDG_CACHE_HOME"); dir && *dir) return fs::path(dir) / "olt";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "olt";
  return job_dir / ".olt-cache";
}

Job load_job(const fs::path& file, const std::vector<KindSpec>& kinds) {
  Job job;
  job.file = fs::absolute(file).lexically_normal();
  job.document = load_yaml(file);
  const Document& doc = job.document;
  const fs::path base = job.file.parent_path();

  std::vector<Diagnostic> errors = validate_against_schema(doc, "job.schema.json");
  // Semantic errors are more precise than the schema's at the same place: keep one per position.
  auto report = [&](const Diagnostic& d) {
    errors.erase(std::remove_if(errors.begin(), errors.end(),
                                [&](const Diagnostic& e) {
                                  return e.line == d.line && e.column == d.column && e.message.rfind("schema ", 0) == 0;
                                }),
                 errors.end());
    errors.push_back(d);
  };
  const json& root = doc.value;
  if (!root.is_object()) throw InputError({doc.error_at("", "expected a map with version, output and stages")});

  auto check_keys = [&](const json& object, const std::string& pointer, const std::vector<std::string>& known,
                        const std::string& what) {
    for (const auto& [key, unused] : object.items()) {
      if (std::count(known.begin(), known.end(), key)) continue;
      std::string message = what + ": unknown key '" + key + "'";
      const std::string guess = did_you_mean(key, known);
      if (!guess.empty()) message += "; did you mean '" + guess + "'?";
      report(doc.error_at_key(pointer + "/" + pointer_escape(key), message));
    }
  };
  check_keys(root, "", {"version", "output", "cache", "stages"}, "job");
  if (root.contains("version") && root["version"].is_number_integer()) job.version = root["version"];
  if (root.contains("output") && root["output"].is_string())
    job.output = resolve_path(base, root["output"].get<std::string>());
  job.cache = root.contains("cache") && root["cache"].is_string() ? resolve_path(base, root["cache"].get<std::string>())
                                                                  : default_cache_dir(base);

  std::map<std::string, StageDecl> stages;
  if (root.contains("stages") && root["stages"].is_object()) {
    for (const auto& [id, body] : root["stages"].items()) {
      StageDecl s;
      s.id = id;
      s.pointer = "/stages/" + pointer_escape(id);
      if (!body.is_object()) continue;  // the schema reported it
      check_keys(body, s.pointer, {"kind", "needs", "params"}, "stage '" + id + "'");
      if (body.contains("kind") && body["kind"].is_string()) s.kind = body["kind"];
      if (body.contains("needs") && body["needs"].is_array())
        for (const auto& need : body["needs"])
          if (need.is_string()) s.needs.push_back(need);
      const KindSpec* kind = find_kind(kinds, s.kind);
      if (!kind) {
        std::vector<std::string> names;
        for (const auto& k : kinds) names.push_back(k.name);
        std::string message = "stage '" + id + "': unknown kind '" + s.kind + "'";
        const std::string guess = did_you_mean(s.kind, names);
        if (!guess.empty()) message += "; did you mean '" + guess + "'?";
        report(doc.error_at(s.pointer + "/kind", message));
      } else {
        std::vector<Diagnostic> param_errors;
        s.params = body.contains("params")
                       ? kind->params->canonical(doc, s.pointer + "/params", base,
                                                 "stage '" + id + "' (" + s.kind + ")", param_errors)
                       : kind->params->defaults();
        for (const auto& d : param_errors) report(d);
      }
      for (size_t i = 0; i < s.needs.size(); ++i) {
        const std::string& need = s.needs[i];
        if (!root["stages"].contains(need)) {
          std::vector<std::string> ids;
          for (const auto& [other, unused] : root["stages"].items()) ids.push_back(other);
          std::string message = "stage '" + id + "': needs '" + need + "', which is not a stage of this job";
          const std::string guess = did_you_mean(need, ids);
          if (!guess.empty()) message += "; did you mean '" + guess + "'?";
          report(doc.error_at(s.pointer + "/needs/" + std::to_string(i), message));
        }
      }
      stages[id] = s;
    }
  }

  // labels.json is written at the output root: one propagate stage per job.
  std::string propagate_stage;
  for (const auto& [id, s] : stages) {
    if (s.kind != "propagate") continue;
    if (propagate_stage.empty())
      propagate_stage = id;
    else
      report(doc.error_at(s.pointer + "/kind", "stage '" + id +
                                                   "': a job has one propagate stage (labels.json is "
                                                   "written at the output root); '" +
                                                   propagate_stage + "' is one"));
  }

  std::vector<std::string> order, cycle;
  if (!topological_order(stages, order, cycle)) {
    std::string path;
    for (const auto& id : cycle) path += (path.empty() ? "" : " -> ") + id;
    report(doc.error_at(stages.at(cycle.front()).pointer + "/needs", "cycle in needs: " + path));
  } else {
    for (const auto& id : order) {
      StageDecl& s = stages.at(id);
      const KindSpec* kind = find_kind(kinds, s.kind);
      if (!kind) continue;
      std::map<std::string, const StageDecl*> upstream;
      const std::vector<std::string> above = ancestors(stages, id);
      auto resolve = [&](const std::string& wanted, bool required) {
        std::vector<std::string> candidates;
        for (const auto& a : above)
          if (stages.at(a).kind == wanted) candidates.push_back(a);
        if (candidates.size() > 1) {
          std::vector<std::string> direct;
          for (const auto& c : candidates)
            if (std::count(s.needs.begin(), s.needs.end(), c)) direct.push_back(c);
          if (direct.size() == 1) candidates = direct;
        }
        if (candidates.size() == 1) {
          s.inputs[wanted] = candidates.front();
          upstream[wanted] = &stages.at(candidates.front());
        } else if (candidates.size() > 1) {
          std::string list;
          for (const auto& c : candidates) list += (list.empty() ? "" : ", ") + c;
          report(doc.error_at(s.pointer + "/needs", "stage '" + id + "': several upstream '" + wanted + "' stages (" +
                                                        list + "); name exactly one in needs"));
        } else if (required) {
          report(doc.error_at_key(doc.values.count(s.pointer + "/needs") ? s.pointer + "/needs" : s.pointer,
                                  "stage '" + id + "' (" + s.kind + "): needs a '" + wanted +
                                      "' stage upstream (directly or through needs)"));
        }
      };
      for (const auto& r : kind->reads) resolve(r, true);
      for (const auto& r : kind->optional_reads) resolve(r, false);
      if (kind->check) {
        std::vector<Diagnostic> more;
        kind->check(s, upstream, doc, more);
        for (const auto& d : more) report(d);
      }
    }
  }
  if (!errors.empty()) {
    std::stable_sort(errors.begin(), errors.end(), [](const Diagnostic& a, const Diagnostic& b) {
      return std::tie(a.line, a.column) < std::tie(b.line, b.column);
    });
    throw InputError(errors);
  }
  for (const auto& id : order) job.stages.push_back(stages.at(id));
  return job;
}

}  // namespace olt
