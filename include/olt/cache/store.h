#pragma once
// The content cache. Layout under the cache folder:
//   objects/<k0k1>/<key>/            one artifact: the files a stage wrote, plus .artifact.json
//                                    {"key", "digest", "files": [{"path", "sha256", "size"
//                                     [, "in": key, "as": path]}], "references": [keys]}: a file
//                                    with "in" is that artifact's file "as" (a frame's file in its
//                                    stage's artifact), referred to, not copied; "references" lists
//                                    those artifacts (gc keeps them while this one is kept)
//   tmp/                             artifacts being written (renamed into objects/ when complete)
//   records/<job id>/<stage id>.json the key inputs of each stage's last run, to explain re-runs:
//                                    {"format": 1, "record": {...}}
//   log.jsonl                        append-only: one line per executed stage, with its reason and
//                                    "format": 1
// Records and log lines carry the version of their format (kRecordFormat): a record of another
// version, or none, is read as absent (a cache miss with "never run"), never as an error, so an
// older or newer OLT sharing the cache re-runs rather than misreads.
//   olt-cache.json                   the marker {"olt_cache": 1}: every run writes it; `olt cache gc`
//                                    removes nothing from a folder without it
//   file-digests.json                memo of input file digests by (path, size, mtime, inode)
//   locks/                           flock files (see olt/cache/lock.h)
//   shards/<job id>/                 finished shards of cluster runs (see runtime/shard_records.h)
// An artifact's digest is the SHA-256 of its sorted "sha256  path" lines: equal digests mean
// equal content, which is what lets an unchanged re-run stop downstream stages from re-running.
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/core/hash.h"
#include "olt/model/artifact.h"

namespace olt {

/// The version of the format of records/ and log.jsonl.
constexpr int kRecordFormat = 1;

class Store {
 public:
  /// The cache at `root`, on `files` (a memory file system in tests).
  explicit Store(fs::path root, FileSystem& files = real_file_system());
  const fs::path& root() const { return root_; }
  FileSystem& files() const { return files_; }

  /// The entry `key` with each of its files there at its listed size; nullopt where it is not, or is
  /// damaged. A process that keeps memory (`olt watch`) checks an entry once, and one it committed
  /// not at all: while its metadata file is the same file, it is the entry known before.
  std::optional<Artifact> find(const std::string& key) const;
  /// Whether an entry under `key` is in place (its metadata file: one stat; its files not checked).
  bool holds(const std::string& key) const;
  /// The entry `key` as its metadata lists it, its files not looked for on the disk (for an entry
  /// found or made before, whose list was let go); nullopt without it.
  std::optional<Artifact> find_unchecked(const std::string& key) const;
  /// A fresh, empty folder where a stage writes the artifact for `key`.
  fs::path begin(const std::string& key) const;
  /// Lists what was written with the files `described` (those referred from other artifacts, their
  /// `in` and `as` set: listed, not copied; and files of `temp` with the digest and size of the bytes
  /// written there, each once, hashed as they were written: the others found in `temp` are hashed
  /// here), and
  /// moves it into place atomically. If another process committed the same key meanwhile, its
  /// artifact is kept and ours discarded.
  /// Not synced: a run syncs the cache once, before it returns. An entry cut short by a power loss
  /// before that sync is not found (a file of another size) and is made again (docs/robustness.md).
  Artifact commit(const std::string& key, const fs::path& temp, ArtifactFiles described = {}) const;
  /// In `olt watch`, the entry `key` no longer remembered as found or made (a stage made another
  /// in its place, which the next cycles find instead): finding it again checks its files. Nothing
  /// where it is not remembered.
  void forget(const std::string& key) const;
  /// In `olt watch`, `keys`, the entries one user of the store used this run (a stage's own entry,
  /// its frames', its pieces), kept under `name`; those it used the run before under that name and
  /// not now are forgotten (forget) and returned. An edit makes such entries again each cycle:
  /// remembered for good, they grew the daemon cycle after cycle. Nothing where nothing is kept.
  std::vector<std::string> forget_unused(const std::string& name, std::vector<std::string> keys) const;
  /// The keys committed through this store since the last take_committed or clear_committed, in no
  /// particular order: what a run removes where the sync that was to make them durable failed. A commit that found the
  /// key committed by another writer does not list it.
  std::vector<std::string> take_committed() const;
  /// Lets go of them without a list: they are durable.
  void clear_committed() const;
  /// Removes the entry `key` alone (not those it refers to files of); nothing for a key not there.
  void remove(const std::string& key) const;
  void discard(const fs::path& temp) const;
  /// Removes the artifact `key` and the artifacts it refers to files of (a damaged entry, so that the
  /// next run computes it anew rather than referring to the same damaged bytes again).
  void drop(const std::string& key) const;
  /// The artifact a folder would be if committed under `key` with `described` (as commit; nothing
  /// moved).
  Artifact describe(const std::string& key, const fs::path& dir, ArtifactFiles described = {}) const;

  /// The stage's record of its job's last run; absent when none, unreadable or of another format.
  std::optional<nlohmann::json> record(const std::string& job_id, const std::string& stage_id) const;
  /// Every readable record of the current format, of every job using the cache.
  std::vector<nlohmann::json> records() const;
  /// Saves the stage's record, unless it is the one there: whether it wrote. Replaced in one step,
  /// not synced: the run syncs the cache before it returns (a record lost to a power loss only
  /// costs `olt plan` its reasons and `olt cache gc` a root).
  bool save_record(const std::string& job_id, const std::string& stage_id, const nlohmann::json& record) const;
  /// Writes the marker (olt-cache.json) where it is missing: this folder is an OLT cache.
  void mark() const;
  bool marked() const;
  /// Appends `entry` (an object) to log.jsonl with the format's version.
  void log(const nlohmann::json& entry) const;

  /// Every committed artifact, re-hashed against its .artifact.json: what is damaged and why.
  struct Problem {
    std::string key;  ///< "" for a folder that is not an artifact
    fs::path dir;
    std::string message;  ///< "file class.png: sha256 differs", ...
  };
  struct Verification {
    size_t artifacts = 0, files = 0;
    uint64_t bytes = 0;
    std::vector<Problem> problems;
  };
  Verification verify() const;

  /// Removes the artifacts not reachable from `roots` through their references, and leftovers of
  /// killed runs in tmp/ older than `min_tmp_age_s`. The caller holds the cache's gc lock. Throws
  /// InputError on a folder without the marker; never follows a symbolic link (an `objects/xx` that
  /// is one is left alone) and removes from tmp/ only what OLT names there (`.tmp.*`).
  struct Collection {
    size_t kept = 0, removed = 0, temporaries = 0;
    uint64_t bytes_freed = 0;
  };
  Collection collect_garbage(const std::set<std::string>& roots, double min_tmp_age_s = 3600) const;

 private:
  fs::path object_dir(const std::string& key) const;
  void remove_object(const fs::path& dir, const std::string& key) const;
  fs::path root_;
  FileSystem& files_;
  mutable std::mutex committed_mutex_;  // commits come from parallel units
  /// The keys committed since take_committed, held until the run's sync. OLT's own, a digest's hex
  /// after a name ("frame-", "piece-" or none), as the digest and the name's place in
  /// committed_names_: 36 bytes each (10,000 frames' as strings took 1.2 MB); any other as it is.
  struct CommittedKey {
    Digest digest;
    uint16_t name = 0;
  };
  mutable std::vector<std::string> committed_names_;
  mutable std::deque<CommittedKey> committed_digests_;
  mutable std::vector<std::string> committed_;
  void add_committed(const std::string& key) const;  ///< with committed_mutex_ held
};

/// SHA-256 of input files, remembered by (path, size, mtime, inode) like git's index, so a plan over
/// thousands of unchanged images does not re-read them.
class FileDigests {
 public:
  explicit FileDigests(fs::path memo_file, FileSystem& files = real_file_system());
  std::string digest(const fs::path& file);  ///< throws InputError naming a missing file
  /// Best effort (the memo is only an optimisation), not synced: whether it wrote.
  bool save() const;

 private:
  fs::path memo_file_;
  FileSystem& files_;
  nlohmann::json memo_;
  bool changed_ = false;
  std::mutex mutex_;
};

}  // namespace olt
