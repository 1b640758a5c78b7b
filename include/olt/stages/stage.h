#pragma once
// The runtime's view of a stage kind: its validation spec, a version constant that enters every
// cache key (bump it when the kind's output for the same inputs changes), the input files it
// reads (hashed into the key before it runs), and the function that runs it. A run writes its
// artifact into `dir`: data files for downstream stages, files it publishes to the output folder,
// and a summary of what it found. Stages see neither the cache nor the job: the runtime hands them
// the stage's declaration, its input artifacts and a digest function for input files. A kind that
// works in units (frames) declares them, each with the record of what it is made of; the runtime
// keys, finds, runs, shards and explains the units as it does stages (olt/runtime/units.h).
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "olt/config/stage_decl.h"
#include "olt/core/fs.h"
#include "olt/model/artifact.h"

namespace olt {

struct StageInput {
  std::string stage_id;
  Artifact artifact;
};

/// A file of the artifact that goes to the output folder, with what the manifest says about it.
struct Published {
  std::string file;         ///< path inside the artifact
  std::string path;         ///< path inside the output folder
  std::string kind;         ///< manifest kind: trajectory, scene_ply, class_label, ...
  std::string sensor;       ///< "" when the file does not belong to one sensor
  std::string observation;  ///< observation id, "" when the file does not belong to one
  double timestamp = 0;     ///< of the observation's depth image
};

nlohmann::json to_json(const Published& p);
Published published_from_json(const nlohmann::json& j);

struct StageRun {
  fs::path job_file;  ///< the job's file, for names in reports
  const StageDecl& stage;
  const std::map<std::string, StageInput>& inputs;  ///< by artifact kind
  fs::path dir;                                     ///< where the artifact is written
  /// SHA-256 of an input file (remembered across runs by the runtime); throws InputError naming a
  /// missing file.
  std::function<std::string(const fs::path&)> digest_file;
  std::vector<Published> published;
  nlohmann::json summary = nlohmann::json::object();  ///< counts and flags, saved as summary.json
  /// About this run only (e.g. how much was reused from the cache): logged, not saved, so that it
  /// cannot make two runs with equal results differ.
  nlohmann::json report = nlohmann::json::object();
  std::map<std::string, std::string> linked;  ///< files linked from other artifacts: path -> sha256
  std::set<std::string> references;           ///< keys of the artifacts files were linked from
  std::mutex linked_mutex;

  const StageInput* input(const std::string& kind) const;
  /// Writes `bytes` to the artifact at `file` (a path inside the artifact).
  void write(const std::string& file, std::string_view bytes);
  /// Puts `from`'s file `from_file` into the artifact at `file` without copying its bytes (a hard
  /// link; a copy where the file system has none). Thread-safe.
  void link(const std::string& file, const Artifact& from, const std::string& from_file);
  void publish(const std::string& file, const std::string& output_path, const std::string& kind,
               const std::string& sensor = "", const std::string& observation = "", double timestamp = 0);
};

/// One unit of a stage's work, cached as an entry of its own: its name ("sensor/observation") and
/// the record of what its files are computed from (its hash is the entry's key; `olt plan` compares
/// it with the previous run's to say why the unit runs again).
struct Unit {
  std::string name;
  nlohmann::json record;
};

/// A stage's work split into units for one run, its inputs loaded.
class UnitWork {
 public:
  virtual ~UnitWork() = default;
  /// One per position of the recording (shards split by position); none where the unit is not made
  /// in this run (e.g. an observation whose pose is flagged).
  virtual const std::vector<std::optional<Unit>>& units() const = 0;
  /// Writes unit `i`'s files into the empty folder `dir`. Called from several threads at once.
  virtual void run(size_t i, const fs::path& dir) const = 0;
  /// Builds the stage's artifact from the units' entries (by position; none where units() has none).
  virtual void assemble(const std::vector<std::optional<Artifact>>& entries, StageRun& run) const = 0;
};

/// How `olt plan` speaks of a kind's units: "3 of 12 frames to label; frames seeing changed box b1 (3)".
struct UnitWords {
  std::string unit = "unit";        ///< frame
  std::string verb = "run";         ///< label
  std::string members;              ///< the record's part whose members are named when they change: boxes
  std::string member = "member";    ///< box
  std::string holding = "holding";  ///< seeing
};

struct StageKind {
  KindSpec spec;
  int version = 1;
  /// Files the stage will read, resolved from its params (throws InputError on bad input).
  std::function<std::vector<fs::path>(const StageDecl&)> files_read;
  std::function<void(StageRun&)> run;
  /// Cheap enough (milliseconds) for `olt plan` to run aside, so it can look further ahead.
  bool light = false;
  /// Works in units, each a cache entry of its own (null: the stage is one unit): on a cluster the
  /// units are split across shards, and the artifact is assembled by `olt merge`. Given the run's
  /// inputs (`dir` empty: nothing may be written).
  std::function<std::unique_ptr<const UnitWork>(const StageRun&)> units;
  UnitWords unit_words;
  /// For `olt plan --units`: the units' names in the recording's order, the order shards split them
  /// in, from the source alone; kinds with units only.
  std::function<std::vector<std::string>(const StageInput& source)> unit_names;
};

/// A kind from its four main parts (`files_read` null: the stage reads no files named in its params);
/// the optional ones (light, units, unit_words, unit_names) are set on the result.
StageKind make_stage_kind(KindSpec spec, int version, std::function<std::vector<fs::path>(const StageDecl&)> files_read,
                          std::function<void(StageRun&)> run);

/// Every stage kind, in the order `olt help` lists them.
const std::vector<StageKind>& stage_kinds();
std::vector<KindSpec> kind_specs();
const StageKind& stage_kind(const std::string& name);

}  // namespace olt
