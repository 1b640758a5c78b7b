#include "olt/runtime/units.h"

#include <functional>
#include <set>

#include "olt/runtime/runner.h"
#include "olt/stages/stage.h"

namespace olt {

std::map<std::string, StageRole> stage_roles(const Job& job, const Environment& env) {
  std::map<std::string, const StageDecl*> by_id;
  for (const auto& s : job.stages) by_id[s.id] = &s;
  // Stages each stage needs, directly or not.
  std::map<std::string, std::set<std::string>> upstream;
  std::function<const std::set<std::string>&(const std::string&)> all_needs =
      [&](const std::string& id) -> const std::set<std::string>& {
    auto it = upstream.find(id);
    if (it != upstream.end()) return it->second;
    std::set<std::string> needs;
    for (const auto& n : by_id.at(id)->needs) {
      needs.insert(n);
      const auto& further = all_needs(n);
      needs.insert(further.begin(), further.end());
    }
    return upstream[id] = std::move(needs);
  };
  std::set<std::string> frames, before;
  for (const auto& s : job.stages)
    if (env.kind(s.kind).units) {
      frames.insert(s.id);
      const auto& needs = all_needs(s.id);
      before.insert(needs.begin(), needs.end());
    }
  std::map<std::string, StageRole> roles;
  for (const auto& s : job.stages) {
    const auto& needs = all_needs(s.id);
    const bool after = std::any_of(needs.begin(), needs.end(), [&](const auto& n) { return frames.count(n) > 0; });
    roles[s.id] = frames.count(s.id)   ? StageRole::frames
                  : after              ? StageRole::after_frames
                  : before.count(s.id) ? StageRole::before_frames
                                       : StageRole::independent;
  }
  return roles;
}

int owner_shard(const Job& job, const std::map<std::string, StageRole>& roles, const std::string& stage_id, int count) {
  int ordinal = 0;
  for (const auto& s : job.stages) {
    if (roles.at(s.id) != StageRole::independent) continue;
    if (s.id == stage_id) return ordinal % count;
    ++ordinal;
  }
  return 0;
}

nlohmann::json plan_units(const Job& job, int shards) {
  const auto roles = stage_roles(job);
  std::map<std::string, std::vector<std::string>> frames;
  PlanOptions options;
  options.unit_names = true;
  for (const auto& s : plan_job(job, options))
    if (!s.unit_names.empty()) frames[s.id] = s.unit_names;
  nlohmann::json units = nlohmann::json::array();
  for (const auto& s : job.stages) {
    const StageRole role = roles.at(s.id);
    nlohmann::json unit = {{"unit", s.id}, {"stage", s.id}, {"kind", s.kind}};
    if (role == StageRole::frames) {
      const auto& list = frames[s.id];
      for (size_t k = 0; k < list.size(); ++k) {
        nlohmann::json frame = unit;
        frame["unit"] = s.id + ":" + list[k];
        frame["scope"] = "frame";
        frame["frame"] = list[k];
        frame["shard"] = static_cast<int>(k % static_cast<size_t>(shards));
        units.push_back(frame);
      }
      continue;
    }
    unit["scope"] = role == StageRole::after_frames ? "merge" : "sequence";
    if (role == StageRole::after_frames)
      unit["shard"] = "merge";
    else if (role == StageRole::before_frames)
      unit["shard"] = "any";
    else
      unit["shard"] = owner_shard(job, roles, s.id, shards);
    units.push_back(unit);
  }
  return {{"job", job.file.string()}, {"shards", shards}, {"units", units}};
}

}  // namespace olt
