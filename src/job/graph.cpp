#include "graph.h"

#include <algorithm>
#include <set>

namespace olt {

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

}  // namespace olt
