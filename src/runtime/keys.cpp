#include "keys.h"

#include "olt/core/hash.h"

namespace olt {

nlohmann::json key_record(const StageDecl& stage, const StageKind& kind,
                          const std::map<std::string, std::string>& input_digests, FileDigests& digests) {
  nlohmann::json files = nlohmann::json::object();
  for (const auto& f : kind.files_read(stage)) files[f.string()] = digests.digest(f);
  return {{"kind", stage.kind},
          {"version", kind.version},
          {"params", stage.params},
          {"inputs", input_digests},
          {"files", files}};
}

std::string key_of(const nlohmann::json& record) { return sha256_hex(record.dump()); }

std::string rerun_reason(const StageDecl& stage, const nlohmann::json& record,
                         const std::optional<nlohmann::json>& previous) {
  if (!previous) return "never run";
  const auto& old = *previous;
  if (old.value("kind", "") != record["kind"] || old.value("version", 0) != record["version"])
    return "stage kind version changed";
  if (old.value("params", nlohmann::json()) != record["params"]) {
    std::string keys;
    for (const auto& [key, value] : record["params"].items())
      if (!old["params"].contains(key) || old["params"][key] != value) keys += (keys.empty() ? "" : ", ") + key;
    return "params changed: " + keys;
  }
  for (const auto& [kind, digest] : record["inputs"].items())
    if (!old["inputs"].contains(kind) || old["inputs"][kind] != digest)
      return "input " + stage.inputs.at(kind) + " changed";
  std::string changed;
  int count = 0;
  for (const auto& [file, digest] : record["files"].items()) {
    if (old["files"].contains(file) && old["files"][file] == digest) continue;
    if (++count == 1) changed = file;
  }
  if (count == 1) return "file " + changed + " changed";
  if (count > 1) return "file " + changed + " and " + std::to_string(count - 1) + " other files changed";
  if (old["files"].size() != record["files"].size()) return "set of input files changed";
  return "not in the cache";
}

std::string job_id(const Job& job) { return sha256_hex(job.file.string()).substr(0, 16); }

std::string job_digest(const Job& job, FileDigests& digests) {
  nlohmann::json stages = nlohmann::json::array();
  for (const auto& stage : job.stages)
    stages.push_back(
        {{"id", stage.id}, {"needs", stage.needs}, {"key", key_record(stage, stage_kind(stage.kind), {}, digests)}});
  return sha256_hex(stages.dump());
}

}  // namespace olt
