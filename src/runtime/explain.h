#pragma once
// Why something runs again: the one comparison of what a result is made of (its key record) with
// what it was made of in the previous run, for stages and their units alike (private to the runtime).
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "olt/job/job.h"

namespace olt {

/// How a key record differs from the previous one: its parts (top-level fields) that differ, and for
/// parts compared member by member (params, files, boxes), the members added, removed or changed.
struct RecordChange {
  std::vector<std::string> parts;                           ///< differing parts compared whole
  std::map<std::string, std::vector<std::string>> members;  ///< part -> differing members
  bool empty() const { return parts.empty() && members.empty(); }
};

RecordChange diff_records(const nlohmann::json& now, const nlohmann::json& before,
                          const std::set<std::string>& by_member);

/// Why a stage with key record `record` must run, given the record of its previous run (if any):
/// never run, stage kind version changed, params changed: a, b, input X changed, file F changed, ...
std::string rerun_reason(const StageDecl& stage, const nlohmann::json& record,
                         const std::optional<nlohmann::json>& previous);

}  // namespace olt
