#include "olt/runtime/runner.h"

#include <spdlog/spdlog.h>

#include <chrono>

#include "keys.h"
#include "olt/core/error.h"
#include "olt/runtime/publish.h"
#include "olt/stages/stage.h"

namespace olt {
namespace {

std::map<std::string, StageInput> stage_inputs(const StageDecl& stage, const std::map<std::string, Artifact>& done) {
  std::map<std::string, StageInput> inputs;
  for (const auto& [kind, id] : stage.inputs) inputs[kind] = {id, done.at(id)};
  return inputs;
}

std::map<std::string, std::string> input_digests(const std::map<std::string, StageInput>& inputs) {
  std::map<std::string, std::string> digests;
  for (const auto& [kind, input] : inputs) digests[kind] = input.artifact.digest;
  return digests;
}

// Runs one stage into a fresh artifact folder and commits it; nothing is left behind on failure.
Artifact execute(const Job& job, const StageDecl& stage, const StageKind& kind,
                 const std::map<std::string, StageInput>& inputs, const std::string& key, const Store& store,
                 FileDigests& digests, nlohmann::json* summary) {
  const fs::path dir = store.begin(key);
  try {
    StageRun run{job, stage, inputs, dir, digests, {}, nlohmann::json::object()};
    kind.run(run);
    nlohmann::json published = nlohmann::json::array();
    for (const auto& p : run.published) published.push_back(to_json(p));
    run.write("publish.json", published.dump(1));
    run.write("summary.json", run.summary.dump(1));
    *summary = run.summary;
    return store.commit(key, dir);
  } catch (const InputError&) {
    store.discard(dir);
    throw;
  } catch (const std::exception& e) {
    store.discard(dir);
    throw StageFailure(stage.id, e.what());
  }
}

}  // namespace

std::vector<StageStatus> plan_job(const Job& job) {
  const Store store(job.cache);
  FileDigests digests(job.cache / "file-digests.json");
  std::map<std::string, Artifact> done;
  std::vector<StageStatus> plan;
  for (const auto& stage : job.stages) {
    StageStatus status{stage.id, stage.kind, "run", "", 0, nullptr};
    std::string pending;
    for (const auto& [kind, id] : stage.inputs)
      if (!done.count(id) && pending.empty()) pending = id;
    if (!pending.empty()) {
      status.reason = "input " + pending + " will be re-run";
    } else {
      const nlohmann::json record =
          key_record(stage, stage_kind(stage.kind), input_digests(stage_inputs(stage, done)), digests);
      if (auto artifact = store.find(key_of(record))) {
        status.status = "cached";
        status.reason = "unchanged";
        done[stage.id] = *artifact;
      } else {
        status.reason = rerun_reason(stage, record, store.record(job_id(job), stage.id));
      }
    }
    plan.push_back(status);
  }
  digests.save();
  return plan;
}

std::vector<StageStatus> run_job(const Job& job) {
  const Store store(job.cache);
  FileDigests digests(job.cache / "file-digests.json");
  std::map<std::string, Artifact> done;
  std::vector<StageStatus> report;
  const size_t total = job.stages.size();
  for (const auto& stage : job.stages) {
    const auto start = std::chrono::steady_clock::now();
    const StageKind& kind = stage_kind(stage.kind);
    const auto inputs = stage_inputs(stage, done);
    const nlohmann::json record = key_record(stage, kind, input_digests(inputs), digests);
    const std::string key = key_of(record);
    StageStatus status{stage.id, stage.kind, "cached", "unchanged", 0, nullptr};
    const std::string counter = "[" + std::to_string(report.size() + 1) + "/" + std::to_string(total) + "] ";
    if (auto artifact = store.find(key)) {
      done[stage.id] = *artifact;
      status.summary = nlohmann::json::parse(read_file(artifact->dir / "summary.json"));
      spdlog::info("{}{} ({}): cached", counter, stage.id, stage.kind);
    } else {
      status.status = "ran";
      status.reason = rerun_reason(stage, record, store.record(job_id(job), stage.id));
      spdlog::info("{}{} ({}): running ({})", counter, stage.id, stage.kind, status.reason);
      done[stage.id] = execute(job, stage, kind, inputs, key, store, digests, &status.summary);
      status.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      spdlog::info("{}{} ({}): done in {:.2f} s: {}", counter, stage.id, stage.kind, status.seconds,
                   status.summary.dump());
      store.log({{"job", job.file.string()},
                 {"stage", stage.id},
                 {"key", key},
                 {"reason", status.reason},
                 {"digest", done[stage.id].digest},
                 {"seconds", status.seconds}});
    }
    store.save_record(job_id(job), stage.id, record);
    report.push_back(status);
  }
  digests.save();
  std::vector<std::pair<std::string, Artifact>> artifacts;
  for (const auto& stage : job.stages) artifacts.emplace_back(stage.id, done.at(stage.id));
  publish_outputs(job.output, artifacts);
  return report;
}

}  // namespace olt
