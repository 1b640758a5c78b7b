// `olt plan`: what `olt run` would do, stage by stage, without running anything but light stages
// (aside, in folders removed at the end) so that it can look further ahead.
#include <spdlog/spdlog.h>

#include "execute.h"
#include "explain.h"
#include "keys.h"
#include "olt/runtime/runner.h"
#include "unit_engine.h"

namespace olt {
namespace {

class Planner {
 public:
  Planner(const Job& job, const PlanOptions& options)
      : job_(job),
        options_(options),
        store_(job.cache, *options.env.files),
        digests_(job.cache / "file-digests.json", *options.env.files) {}
  Planner(const Planner&) = delete;
  Planner& operator=(const Planner&) = delete;
  ~Planner() {
    for (const auto& dir : aside_) {
      try {
        store_.discard(dir);
      } catch (const std::exception& e) {
        spdlog::warn("plan: could not remove {}: {}", dir.string(), e.what());
      }
    }
  }

  StageStatus plan(const StageDecl& stage) {
    StageStatus status{stage.id, stage.kind, "run", "", 0, nullptr, nullptr, {}};
    const StageKind& kind = options_.env.kind(stage.kind);
    if (options_.unit_names) as_stage(stage, [&] { status.unit_names = unit_names(stage, kind); });
    for (const auto& [input_kind, id] : stage.inputs)
      if (!done_.count(id)) {
        status.reason = store_.record(job_id(job_), stage.id) ? "input " + id + " will be re-run" : "never run";
        return status;
      }
    const auto inputs = stage_inputs(stage, done_);
    const nlohmann::json record = key_record(job_, stage, kind, input_digests(inputs), digests_);
    const std::string key = key_of(record);
    if (auto artifact = store_.find(key)) {
      done_[stage.id] = *artifact;
      return {stage.id, stage.kind, "cached", "unchanged", 0, nullptr, nullptr, status.unit_names};
    }
    status.reason = rerun_reason(stage, record, store_.record(job_id(job_), stage.id));
    const StageContext context = stage_context(job_, stage, inputs, digests_);
    if (kind.units)
      as_stage(stage, [&] {
        status.detail =
            explain_units(*kind.units(context), kind.unit_words, store_, previous_artifact(job_, stage, store_));
      });
    // Light stages run aside to look further ahead; with --units, so do the sources the units are
    // named from.
    if (kind.light || (options_.unit_names && stage.kind == "source")) run_aside(context, kind, key);
    return status;
  }

  void save_digests() { digests_.save(); }

 private:
  // The units' names of a stage with units, once its source is known.
  std::vector<std::string> unit_names(const StageDecl& stage, const StageKind& kind) const {
    const auto source = stage.inputs.find("source");
    if (!kind.unit_names || source == stage.inputs.end() || !done_.count(source->second)) return {};
    return kind.unit_names({source->second, done_.at(source->second)});
  }

  void run_aside(const StageContext& context, const StageKind& kind, const std::string& key) {
    const fs::path dir = store_.begin(key);
    aside_.push_back(dir);
    ArtifactFolder out(dir, store_.files());
    run_into(context, kind, store_, out);
    done_[context.stage.id] = store_.describe(key, dir, out.take_described());
  }

  const Job& job_;
  const PlanOptions& options_;
  const Store store_;
  FileDigests digests_;
  std::map<std::string, Artifact> done_;  // cached, or run aside (light stages) to look further ahead
  std::vector<fs::path> aside_;           // folders of the stages run aside, removed at the end
};

}  // namespace

std::vector<StageStatus> plan_job(const Job& job, const PlanOptions& options) {
  Planner planner(job, options);
  std::vector<StageStatus> plan;
  for (const auto& stage : job.stages) plan.push_back(planner.plan(stage));
  planner.save_digests();
  return plan;
}

}  // namespace olt
