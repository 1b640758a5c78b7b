#pragma once
// Records of finished shards, in the shared cache (private to the runtime):
//   CACHE/shards/<job id>/<i>-of-<N>.json  {"job", "job_digest", "shard", "count", "finished_unix_s"}
// written atomically when shard i/N finished; `olt merge` reads them to know whether every shard
// finished on the job's current inputs.
#include <string>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/job/job.h"
#include "olt/runtime/shard.h"

namespace olt {

void record_finished_shard(FileSystem& files, const Job& job, const Shard& shard, const std::string& job_digest);

/// The shard count to merge, after checking that shards 0..N-1 all finished with `job_digest`;
/// throws ShardsIncomplete naming the missing shards (or saying none ran) otherwise.
int check_finished_shards(const FileSystem& files, const Job& job, const std::string& job_digest);

}  // namespace olt
