#pragma once
// The job's stage graph (private to job/): an order in which every stage comes after what it needs,
// and what a stage needs directly or not.
#include <map>
#include <string>
#include <vector>

#include "olt/config/stage_decl.h"

namespace olt {

/// Kahn's algorithm; ties by id so the order is stable. Returns false (with the cycle) on a cycle.
bool topological_order(const std::map<std::string, StageDecl>& stages, std::vector<std::string>& order,
                       std::vector<std::string>& cycle);

/// All stages reachable through `needs` from `id`, nearest first.
std::vector<std::string> ancestors(const std::map<std::string, StageDecl>& stages, const std::string& id);

}  // namespace olt
