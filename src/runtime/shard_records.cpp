#include "shard_records.h"

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "keys.h"
#include "olt/core/error.h"
#include "olt/core/file_system.h"

namespace olt {
namespace {

fs::path shards_dir(const Job& job) { return job.cache / "shards" / job_id(job); }

}  // namespace

void record_finished_shard(FileSystem& files, const Job& job, const Shard& shard, const std::string& job_digest) {
  const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  const nlohmann::json record = {{"job", job.file.string()},
                                 {"job_digest", job_digest},
                                 {"shard", shard.index},
                                 {"count", shard.count},
                                 {"finished_unix_s", now}};
  files.write_atomic(shards_dir(job) / (std::to_string(shard.index) + "-of-" + std::to_string(shard.count) + ".json"),
                     record.dump(1) + "\n");
}

int check_finished_shards(const FileSystem& files, const Job& job, const std::string& job_digest) {
  const fs::path dir = shards_dir(job);
  std::map<int, std::set<int>> current, stale;  // count -> finished shard indices
  std::map<int, double> newest;                 // count -> newest finish on the current inputs
  for (const auto& name : files.list(dir)) {
    if (!files.stat(dir / name).is_file()) continue;
    const auto record = nlohmann::json::parse(files.read(dir / name), nullptr, false);
    if (!record.is_object() || !record.contains("count") || !record.contains("shard") ||
        !record["count"].is_number_integer() || !record["shard"].is_number_integer())
      continue;
    const int count = record["count"], shard = record["shard"];
    if (record.value("job_digest", "") == job_digest) {
      current[count].insert(shard);
      newest[count] = std::max(newest[count], record.value("finished_unix_s", 0.0));
    } else {
      stale[count].insert(shard);
    }
  }
  if (current.empty()) {
    if (stale.empty())
      throw ShardsIncomplete("no shard of " + job.file.string() + " has finished (nothing in " + dir.string() +
                             "): run `olt run JOB --shard i/N` for every i first");
    throw ShardsIncomplete("the shards recorded in " + dir.string() +
                           " ran on other inputs (the job or a file it reads changed since): run them again");
  }
  int count = current.begin()->first;
  for (const auto& [n, when] : newest)
    if (when > newest[count]) count = n;
  std::string missing;
  int n_missing = 0;
  for (int i = 0; i < count; ++i) {
    if (current[count].count(i)) continue;
    ++n_missing;
    missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(count) +
               (stale[count].count(i) ? " (ran on other inputs)" : "");
  }
  if (n_missing > 0)
    throw ShardsIncomplete(std::string(n_missing == 1 ? "shard " : "shards ") + missing + " of " + job.file.string() +
                           (n_missing == 1 ? " has" : " have") + " not finished: nothing was merged");
  return count;
}

}  // namespace olt
