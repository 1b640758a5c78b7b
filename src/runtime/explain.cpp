#include "explain.h"

#include <algorithm>

namespace olt {

RecordChange diff_records(const nlohmann::json& now, const nlohmann::json& before,
                          const std::set<std::string>& by_member) {
  RecordChange change;
  auto part_of = [](const nlohmann::json& record, const std::string& key) {
    return record.contains(key) ? record[key] : nlohmann::json();
  };
  std::set<std::string> keys;
  for (const auto& [key, value] : now.items()) keys.insert(key);
  for (const auto& [key, value] : before.items()) keys.insert(key);
  for (const auto& key : keys) {
    const nlohmann::json a = part_of(now, key), b = part_of(before, key);
    if (a == b) continue;
    if (!by_member.count(key) || !a.is_object() || !b.is_object()) {
      change.parts.push_back(key);
      continue;
    }
    auto& members = change.members[key];
    for (const auto& [member, value] : a.items())
      if (!b.contains(member) || b[member] != value) members.push_back(member);
    for (const auto& [member, value] : b.items())
      if (!a.contains(member)) members.push_back(member);
  }
  return change;
}

namespace {

// The keys whose values differ between two params objects, nested ones as dotted paths
// (registration.solver.method).
std::vector<std::string> changed_leaves(const nlohmann::json& now, const nlohmann::json& before,
                                        const std::string& prefix) {
  std::vector<std::string> leaves;
  if (!now.is_object() || !before.is_object()) return {prefix.empty() ? std::string() : prefix};
  std::set<std::string> keys;
  for (const auto& [key, value] : now.items()) keys.insert(key);
  for (const auto& [key, value] : before.items()) keys.insert(key);
  for (const auto& key : keys) {
    const nlohmann::json a = now.contains(key) ? now[key] : nlohmann::json();
    const nlohmann::json b = before.contains(key) ? before[key] : nlohmann::json();
    if (a == b) continue;
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    if (a.is_object() && b.is_object()) {
      const auto deeper = changed_leaves(a, b, path);
      leaves.insert(leaves.end(), deeper.begin(), deeper.end());
    } else {
      leaves.push_back(path);
    }
  }
  return leaves;
}

}  // namespace

std::string rerun_reason(const StageDecl& stage, const nlohmann::json& record,
                         const std::optional<nlohmann::json>& previous) {
  if (!previous) return "never run";
  const RecordChange change = diff_records(record, *previous, {"params", "inputs", "files"});
  auto changed = [&](const std::string& part) {
    return std::find(change.parts.begin(), change.parts.end(), part) != change.parts.end();
  };
  if (changed("kind") || changed("version")) return "stage kind version changed";
  if (changed("output")) return "the output folder moved (its files name paths relative to it)";
  auto members = [&](const std::string& part) {
    auto it = change.members.find(part);
    return it == change.members.end() ? std::vector<std::string>() : it->second;
  };
  if (changed("params") || !members("params").empty()) {
    std::string keys;
    for (const auto& key :
         changed_leaves(record.value("params", nlohmann::json()), previous->value("params", nlohmann::json()), ""))
      keys += (keys.empty() ? "" : ", ") + key;
    return keys.empty() ? "params changed" : "params changed: " + keys;
  }
  for (const auto& kind : members("inputs")) {
    auto it = stage.inputs.find(kind);
    return "input " + (it == stage.inputs.end() ? kind : it->second) + " changed";
  }
  if (changed("inputs")) return "inputs changed";
  const auto files = members("files");
  if (files.size() == 1) return "file " + files[0] + " changed";
  if (files.size() > 1) return "file " + files[0] + " and " + std::to_string(files.size() - 1) + " other files changed";
  if (changed("files")) return "set of input files changed";
  return "not in the cache";
}

}  // namespace olt
