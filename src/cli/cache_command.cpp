// `olt cache verify JOB` and `olt cache gc JOB`: the job's cache checked entry by entry, or pruned.
#include <cstdio>

#include "args.h"
#include "olt/core/error.h"
#include "olt/job/job.h"
#include "olt/runtime/runner.h"
#include "olt/stages/stage.h"

namespace olt {

int cmd_cache(const Args& args) {
  const std::string& action = args.positional.at(0);
  if (action != "verify" && action != "gc")
    throw InputError("olt cache", "unknown action '" + action + "' (expected: verify or gc)");
  const Job job = load_job(args.positional.at(1), kind_specs());
  if (action == "verify") {
    const Store::Verification v = Store(job.cache).verify();
    for (const auto& p : v.problems) std::printf("damaged %s: %s\n", p.dir.string().c_str(), p.message.c_str());
    std::printf("%s: %zu artifacts, %zu files, %.1f MB checked; %zu damaged\n", job.cache.string().c_str(), v.artifacts,
                v.files, v.bytes / 1e6, v.problems.size());
    return v.problems.empty() ? kExitOk : kExitStageFailed;
  }
  const Store::Collection c = collect_cache_garbage(job.cache);
  std::printf("%s: kept %zu artifacts, removed %zu unreferenced and %zu leftovers of killed runs, freed %.1f MB\n",
              job.cache.string().c_str(), c.kept, c.removed, c.temporaries, c.bytes_freed / 1e6);
  return kExitOk;
}

}  // namespace olt
