#pragma once
// The job graph: a YAML file with `version`, `output`, `cache` and `stages`, each stage
// `{kind, needs: [ids], params: {...}}`. Loading validates everything before anything runs: the
// JSON schema (schemas/job.schema.json), then per-kind parameters, the graph (missing needs,
// cycles, which upstream stage feeds each input) and input files. All problems are reported at
// once as FILE:LINE:COLUMN diagnostics in one InputError.
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/config/document.h"
#include "olt/config/params.h"
#include "olt/config/stage_decl.h"

namespace olt {

struct Job {
  fs::path file;  ///< absolute path of the job file
  int version = 1;
  fs::path output;                ///< absolute
  fs::path cache;                 ///< absolute
  std::vector<StageDecl> stages;  ///< in a dependency order (ties broken by id)
  Document document;              ///< the parsed file, for positions in later messages
  /// Per stage id, the files the stage reads, listed (and so checked) once when the job was loaded to
  /// run (load_runnable_job); a run's keys and `olt watch` take them from here rather than parse the
  /// files again (a TUM trajectory three times a watch cycle). A stage missing: listed when needed.
  std::map<std::string, std::vector<fs::path>> files_read;

  const StageDecl& stage(const std::string& id) const;
};

/// The job's stages in steps, each step a stretch of their order in which no stage needs or reads
/// another of the same step, so that its stages may run side by side (the export and the report,
/// which both read the labels and not each other): places in `stages`, every stage once, in order.
std::vector<std::vector<size_t>> stage_steps(const Job& job);

/// Loads and validates a job; throws InputError listing every problem.
Job load_job(const fs::path& file, const std::vector<KindSpec>& kinds);

/// The cache folder used when a job names none: $OLT_CACHE_DIR, else $XDG_CACHE_HOME/olt,
/// else ~/.cache/olt, else .olt-cache beside the job file.
fs::path default_cache_dir(const fs::path& job_dir);

}  // namespace olt
