#include "keys.h"

#include "olt/core/hash.h"

namespace olt {

nlohmann::json key_record(const Job& job, const StageDecl& stage, const StageKind& kind,
                          const std::map<std::string, std::string>& input_digests, FileDigests& digests) {
  nlohmann::json files = nlohmann::json::object();
  const auto listed = job.files_read.find(stage.id);  // none: a job not loaded to run (a test's)
  const std::vector<fs::path> own = listed == job.files_read.end() ? kind.files_read(stage) : std::vector<fs::path>();
  for (const auto& f : listed == job.files_read.end() ? own : listed->second) files[f.string()] = digests.digest(f);
  nlohmann::json record = {{"kind", stage.kind},
                           {"version", kind.version},
                           {"params", stage.params},
                           {"inputs", input_digests},
                           {"files", files}};
  if (kind.reads_output) record["output"] = job.output.string();
  return record;
}

std::string key_of(const nlohmann::json& record) { return sha256_hex(record.dump()); }

std::string job_id(const Job& job) { return sha256_hex(job.file.string()).substr(0, 16); }

std::string job_digest(const Job& job, FileDigests& digests, const Environment& env) {
  nlohmann::json stages = nlohmann::json::array();
  for (const auto& stage : job.stages)
    stages.push_back(
        {{"id", stage.id}, {"needs", stage.needs}, {"key", key_record(job, stage, env.kind(stage.kind), {}, digests)}});
  return sha256_hex(stages.dump());
}

}  // namespace olt
