// `olt help KIND`: what a stage kind reads and every parameter with its doc, what it accepts and its
// default, from the table that validates jobs (olt/config/params.h).
#include <algorithm>
#include <cstdio>

#include "args.h"
#include "olt/stages/stage.h"

namespace olt {

bool print_kind_help(const std::string& name) {
  auto found =
      std::find_if(stage_kinds().begin(), stage_kinds().end(), [&](const StageKind& k) { return k.spec.name == name; });
  if (found == stage_kinds().end()) return false;
  const StageKind& kind = *found;
  auto listed = [](const std::vector<std::string>& words) { return words.empty() ? "nothing" : join(words); };
  std::printf("stage kind %s (version %d)\n  reads: %s", kind.spec.name.c_str(), kind.version,
              listed(kind.spec.reads).c_str());
  if (!kind.spec.optional_reads.empty())
    std::printf("; uses when upstream: %s", listed(kind.spec.optional_reads).c_str());
  std::printf("\n\nparameters (under the stage's params:):\n%s", params_help(*kind.spec.params).c_str());
  return true;
}

}  // namespace olt
