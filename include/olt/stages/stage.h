#pragma once
// The runtime's view of a stage kind: its validation spec, a version constant that enters every
// cache key (bump it when the kind's output for the same inputs changes), the input files it
// reads (hashed into the key before it runs), and the function that runs it. A run writes its
// artifact into `dir`: data files for downstream stages, files it publishes to the output folder,
// and a summary of what it found. Stages see neither the cache nor the job: the runtime hands them
// the stage's declaration, its input artifacts, a digest function for input files and a PartStore
// for per-frame entries (olt/runtime's StoreParts backs it with the content store).
#include <functional>
#include <map>
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

/// Which frames of a per-frame stage this process labels: all (a plain run), every count-th from
/// index (a shard of a cluster job, which leaves them in the cache for the merge), or none
/// (`olt merge`: every frame must already be in the cache).
struct FrameShare {
  int index = 0;
  int count = 1;
  bool assemble_only = false;
  bool sharded() const { return count > 1 && !assemble_only; }
  bool owns(size_t frame) const { return count <= 1 || static_cast<int>(frame % static_cast<size_t>(count)) == index; }
};

/// Where a stage keeps parts of its work (frames) as cache entries of their own, keyed by what each
/// part is made of. The runtime gives one backed by its content store (olt/cache/store.h).
class PartStore {
 public:
  virtual ~PartStore() = default;
  virtual std::optional<Artifact> find(const std::string& key) const = 0;
  /// A fresh, empty folder to write the entry for `key` into.
  virtual fs::path begin(const std::string& key) const = 0;
  /// Moves the folder into place as the entry for `key`, without syncing the file system (many small
  /// entries: call sync() once after them).
  virtual Artifact commit(const std::string& key, const fs::path& temp) const = 0;
  virtual void discard(const fs::path& temp) const = 0;
  virtual void sync() const = 0;
};

struct StageRun {
  fs::path job_file;  ///< the job's file, for names in reports
  const StageDecl& stage;
  const std::map<std::string, StageInput>& inputs;  ///< by artifact kind
  fs::path dir;                                     ///< where the artifact is written
  /// SHA-256 of an input file (remembered across runs by the runtime); throws InputError naming a
  /// missing file.
  std::function<std::string(const fs::path&)> digest_file;
  const PartStore& parts;  ///< for stages that cache parts of their work (per frame) as entries of their own
  std::vector<Published> published;
  nlohmann::json summary = nlohmann::json::object();  ///< counts and flags, saved as summary.json
  /// About this run only (e.g. how much was reused from the cache): logged, not saved, so that it
  /// cannot make two runs with equal results differ.
  nlohmann::json report = nlohmann::json::object();
  std::map<std::string, std::string> linked;  ///< files linked from other artifacts: path -> sha256
  std::set<std::string> references;           ///< keys of the artifacts files were linked from
  std::mutex linked_mutex;
  std::optional<Artifact> previous;  ///< this stage's artifact from its last run, when still in the cache
  FrameShare share;                  ///< for per-frame stages

  const StageInput* input(const std::string& kind) const;
  /// Writes `bytes` to the artifact at `file` (a path inside the artifact).
  void write(const std::string& file, std::string_view bytes);
  /// Puts `from`'s file `from_file` into the artifact at `file` without copying its bytes (a hard
  /// link; a copy where the file system has none). Thread-safe.
  void link(const std::string& file, const Artifact& from, const std::string& from_file);
  void publish(const std::string& file, const std::string& output_path, const std::string& kind,
               const std::string& sensor = "", const std::string& observation = "", double timestamp = 0);
};

struct StageKind {
  KindSpec spec;
  int version = 1;
  /// Files the stage will read, resolved from its params (throws InputError on bad input).
  std::function<std::vector<fs::path>(const StageDecl&)> files_read;
  std::function<void(StageRun&)> run;
  /// Cheap enough (milliseconds) for `olt plan` to run aside, so it can look further ahead.
  bool light = false;
  /// For `olt plan`: what running would do in detail (e.g. how many frames and why), given the
  /// inputs; null when not defined. Must not write anything.
  std::function<nlohmann::json(const StageRun&)> plan;
  /// Works frame by frame, each frame a cache entry of its own: on a cluster its frames are split
  /// across shards (run.share), and its artifact is assembled by `olt merge`.
  bool per_frame = false;
  /// For `olt plan --units`: the frames' names ("sensor/observation") in the recording's order, the
  /// order shards split them in; per-frame kinds only.
  std::function<std::vector<std::string>(const StageInput& source)> frame_units;
};

/// A kind from its four main parts (`files_read` null: the stage reads no files named in its params);
/// the optional ones (light, plan, per_frame, frame_units) are set on the result.
StageKind make_stage_kind(KindSpec spec, int version, std::function<std::vector<fs::path>(const StageDecl&)> files_read,
                          std::function<void(StageRun&)> run);

/// Every stage kind, in the order `olt help` lists them.
const std::vector<StageKind>& stage_kinds();
std::vector<KindSpec> kind_specs();
const StageKind& stage_kind(const std::string& name);

}  // namespace olt
