#pragma once
// The runtime's view of a stage kind: its validation spec, a version constant that enters every
// cache key (bump it when the kind's output for the same inputs changes), the input files it
// reads (hashed into the key before it runs), and the function that runs it. A run writes its
// artifact through an ArtifactWriter: data files for downstream stages, files it publishes to the
// output folder; it returns a summary of what it found. Stages see neither the cache nor the job:
// the runtime hands them a StageContext (the stage's declaration, its input artifacts, a digest
// function for input files). A kind that
// works in units (frames) declares them, each with the record of what it is made of; the runtime
// keys, finds, runs, shards and explains the units as it does stages (olt/runtime/units.h).
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "olt/config/stage_decl.h"
#include "olt/core/fs.h"
#include "olt/core/memo.h"
#include "olt/core/pieces.h"
#include "olt/model/artifact.h"

namespace olt {

struct SharedReads;

struct StageInput {
  std::string stage_id;
  const Artifact& artifact;  ///< the runtime's (a stage's artifact lists 70,000 files at 10,000 frames: not copied)
  SharedReads* shared = nullptr;  ///< the run's, where its stages share what they read (artifacts.h); none: read afresh
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

/// What a stage reads: its declaration, its input artifacts by kind, the job's file (for names in
/// reports) and the digests of input files.
struct StageContext {
  fs::path job_file;
  fs::path output;  ///< the job's output folder (absolute); for kinds that say they read it
  const StageDecl& stage;
  const std::map<std::string, StageInput>& inputs;  ///< by artifact kind
  /// SHA-256 of an input file (remembered across runs by the runtime); throws InputError naming a
  /// missing file.
  std::function<std::string(const fs::path&)> digest_file;
  /// Pieces of the stage's work (a picture) kept in the cache on their own by what they are made of,
  /// so a later run asking for the same record gets them without making them. The runtime sets it.
  Memo memo = make_every_time;

  /// The input of artifact kind `kind`, null when the stage has none (optional inputs).
  const StageInput* input(const std::string& kind) const;
  /// The input of a kind the stage's spec requires (the job was validated against it).
  const StageInput& need(const std::string& kind) const;
  /// The name this process keeps `what` of this stage under (`olt watch`, olt/core/process_memory.h):
  /// "what:JOB:STAGE".
  std::string kept_name(std::string_view what) const;
};

/// Where a stage's results go: the artifact the runtime is building (olt/runtime's ArtifactFolder).
class ArtifactWriter {
 public:
  virtual ~ArtifactWriter() = default;
  /// Writes `bytes` to the artifact at `file` (a path inside the artifact). Thread-safe for distinct
  /// files.
  virtual void write(const std::string& file, std::string_view bytes) = 0;
  /// Writes `file` with the text `make` hands to its sink in pieces (a long text, not held whole).
  virtual void write_pieces(const std::string& file, const std::function<void(const PieceSink&)>& make) = 0;
  /// Where a library that writes files itself (PCL's cloud writers) puts the artifact's `file`.
  virtual fs::path path(const std::string& file) = 0;
  /// Puts `from`'s file `from_file` into the artifact at `file` by reference: listed, its bytes left
  /// where they are (nothing copied or linked), read through Artifact::path. Thread-safe.
  virtual void refer(const std::string& file, const Artifact& from, const std::string& from_file) = 0;
  /// Lists a file of the artifact for the output folder.
  virtual void publish(Published published) = 0;
  void publish(const std::string& file, const std::string& output_path, const std::string& kind,
               const std::string& sensor = "", const std::string& observation = "", double timestamp = 0) {
    publish(Published{file, output_path, kind, sensor, observation, timestamp});
  }
};

/// A stage's body: reads its inputs, writes its artifact, returns its summary (counts and flags,
/// saved as summary.json and logged).
using StageFunction = std::function<nlohmann::json(const StageContext&, ArtifactWriter&)>;

/// One unit of a stage's work, cached as an entry of its own: its name ("sensor/observation") and
/// the digest of the record of what its files are computed from (the entry's key; `olt plan`
/// compares the record with the previous run's to say why the unit runs again).
struct Unit {
  std::string name;
  Digest record_sha256;
};

/// The unit `name` of the record `record` (its JSON text, compact: dump(), never empty).
Unit unit_of(std::string name, std::string_view record);

/// A stage's work split into units for one run, its inputs loaded.
class UnitWork {
 public:
  virtual ~UnitWork() = default;
  /// One per position of the recording (shards split by position); none where the unit is not made
  /// in this run (e.g. an observation whose pose is flagged).
  virtual const std::vector<std::optional<Unit>>& units() const = 0;
  /// The record of unit `i` (one units() has), as unit_of was given it: asked for when the unit
  /// runs, for the stage's `<unit>s.json` and by `olt plan`; from several threads at once, once
  /// units() is made. A stage need not hold its records in memory (the labeling stage's are 935
  /// bytes a frame: 93 MB at 100,000 frames).
  virtual std::string record(size_t i) const = 0;
  /// Writes unit `i`'s files into its own empty entry (it publishes nothing: assemble does); true
  /// when it worked in place, from what this process kept of the unit's last run, rather than afresh
  /// (the same files either way: counted for the log). Called from several threads at once.
  virtual bool run(size_t i, ArtifactWriter& out) const = 0;
  /// Takes unit `i`'s entry into the stage's artifact as soon as the unit is found or run (refers to
  /// its files, reads what the summary needs): the entries of 10,000 units are not held at once.
  /// Called once per unit that has one, from several threads at once: it may refer to files and
  /// write files of its own unit; what the stage publishes, in order, is assemble's.
  virtual void take(size_t i, const Artifact& entry, ArtifactWriter& out) = 0;
  /// After every unit was taken and the units' records written: the stage's own files and what it
  /// publishes; returns its summary. It may let its units and their records go (neither units() nor
  /// record() is asked for again).
  virtual nlohmann::json assemble(const StageContext& context, ArtifactWriter& out) = 0;
};

/// How `olt plan` speaks of a kind's units: "3 of 12 frames to label; frames seeing changed box b1 (3)".
struct UnitWords {
  std::string unit = "unit";        ///< frame
  std::string verb = "run";         ///< label
  std::string done = "run";         ///< labeled (the log counts "frames_labeled")
  std::string members;              ///< the record's part whose members are named when they change: boxes
  std::string member = "member";    ///< box
  std::string holding = "holding";  ///< seeing
};

struct StageKind {
  KindSpec spec;
  int version = 1;
  /// Files the stage will read, resolved from its params (throws InputError on bad input).
  std::function<std::vector<fs::path>(const StageDecl&)> files_read;
  StageFunction run;  ///< null for kinds with units
  /// Cheap enough (milliseconds) for `olt plan` to run aside, so it can look further ahead.
  bool light = false;
  /// Its files name paths relative to the output folder (e.g. COCO's image root), so where the
  /// output is enters its key.
  bool reads_output = false;
  /// Works in units, each a cache entry of its own (null: the stage is one unit): on a cluster the
  /// units are split across shards, and the artifact is assembled by `olt merge`.
  std::function<std::unique_ptr<UnitWork>(const StageContext&)> units;
  UnitWords unit_words;
  /// For `olt plan --units`: the units' names in the recording's order, the order shards split them
  /// in, from the source alone; kinds with units only.
  std::function<std::vector<std::string>(const StageInput& source)> unit_names;
  /// By input kind: the only files of that input's list the stage looks up (an input not named here:
  /// any of them). The run may hold just those while it runs: the report looks up the labeling
  /// stage's overlays, not its 70,000 files at 10,000 frames. A file its list does not hold is read
  /// from the artifact's own folder (Artifact::path), so a stage reading files by name keeps at least
  /// the referred ones (referred_file).
  std::map<std::string, FileFilter> looks_up;
};

/// A kind from its four main parts (`files_read` null: the stage reads no files named in its params);
/// the optional ones (light, units, unit_words, unit_names) are set on the result.
StageKind make_stage_kind(KindSpec spec, int version, std::function<std::vector<fs::path>(const StageDecl&)> files_read,
                          StageFunction run);

/// Every stage kind, in the order `olt help` lists them.
const std::vector<StageKind>& stage_kinds();
std::vector<KindSpec> kind_specs();
const StageKind& stage_kind(const std::string& name);

}  // namespace olt
