#pragma once
// Publishing stage outputs into the output folder, and OUTPUT/manifest.json:
//   {"files": [{"path", "sha256", "kind", "stage", "sensor"?, "observation"?: {"id", "timestamp"}}]}
// sorted by path. Only what changed is written: a file the last manifest lists with its digest, and
// that is there with its size, stays as it is; the others are copied from the cache, each hashed on
// the way. All or nothing: the changes (new files, files to remove, the manifest) are first staged
// inside the output and made durable, then the staged folder is renamed to OUTPUT/.olt-publish, and
// only then are the files moved into place, the stale ones removed, the manifest last. A run that
// dies or meets a full disk before that rename leaves the old output as it was; one killed after it
// is finished by the next run (finish_publishing), from the staged files. Files no manifest listed
// (someone's own) and listed files edited by hand are kept; files the last manifest listed that this
// one does not, still holding the listed bytes, are removed (and folders that become empty). Nothing
// is written or removed through a symbolic link inside the output: a path that would pass through
// one is an error naming it. Cache bytes that are not those recorded are a DamagedArtifact, and
// nothing is published. One process publishes into an output at a time (the runner holds the
// cache's "publish" lock).
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "olt/cache/store.h"

namespace olt {

/// A cache file whose bytes are not those its artifact recorded (a disk fault, an edit), found while
/// publishing; nothing of it was published.
class DamagedArtifact : public std::runtime_error {
 public:
  DamagedArtifact(std::string stage, std::string key, const std::string& message)
      : std::runtime_error(message), stage_(std::move(stage)), key_(std::move(key)) {}
  const std::string& stage() const { return stage_; }
  const std::string& key() const { return key_; }

 private:
  std::string stage_, key_;
};

/// Makes the changes a publish killed after staging them left in OUTPUT/.olt-publish, and removes
/// what runs that died before left staged; nothing to do for a whole output.
void finish_publishing(const fs::path& output, FileSystem& files = real_file_system());

/// Folders whose file systems a publish syncs in the same call as its staged changes (the run's
/// cache: one sync for both), and what to do once they are synced (`synced`, called then, and only
/// where there were changes to stage: the output may already hold what it would publish). Where the
/// output's files are clones of the cache's, the folders are synced first on their own, before the
/// clones, and `synced` is called then too (twice in all).
struct SyncAlong {
  std::vector<fs::path> folders;
  std::function<void()> synced;
};

/// The file list of a stage's artifact that came without one (a run lets go of lists the stages
/// after no longer read); throws StageFailure when it cannot be read.
using ListFiles = std::function<ArtifactFiles(const std::string& stage, const Artifact& artifact)>;

/// `artifacts`: (stage id, artifact) of every stage, in run order, on `files`. `listing` (optional): a
/// file, in the cache, where a copy of the output's manifest as paths and digests is kept for the
/// next publish, which reads it instead of the manifest's JSON when it copies the manifest there.
/// An artifact without its file list is listed by `list` if it publishes anything (the source's
/// 30,000 files, at 10,000 observations, are not read again to publish none). The artifacts are let
/// go once the changes are staged, before they are made. `along`: see SyncAlong.
void publish_outputs(const fs::path& output, std::vector<std::pair<std::string, Artifact>> artifacts,
                     FileSystem& files = real_file_system(), const fs::path& listing = {},
                     const ListFiles& list = nullptr, const SyncAlong& along = {});

/// Where a job's cache keeps the listing of the output at `output` (one file per output folder).
fs::path output_listing(const fs::path& cache, const fs::path& output);

}  // namespace olt
