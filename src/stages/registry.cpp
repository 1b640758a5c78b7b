#include "olt/stages/kinds.h"

namespace olt {

const std::vector<StageKind>& stage_kinds() {
  static const std::vector<StageKind> kinds = {source_kind(),    calibrate_kind(),   laser_map_kind(),
                                               poses_kind(),     annotations_kind(), reconstruct_kind(),
                                               propagate_kind(), export_kind(),      report_kind()};
  return kinds;
}

std::vector<KindSpec> kind_specs() {
  std::vector<KindSpec> specs;
  for (const auto& k : stage_kinds()) specs.push_back(k.spec);
  return specs;
}

const StageKind& stage_kind(const std::string& name) {
  for (const auto& k : stage_kinds())
    if (k.spec.name == name) return k;
  throw std::out_of_range("unknown stage kind " + name);
}

}  // namespace olt
