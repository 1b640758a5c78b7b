#pragma once
// Publishing stage outputs into the output folder, and OUTPUT/manifest.json:
//   {"files": [{"path", "sha256", "kind", "stage", "sensor"?, "observation"?: {"id", "timestamp"}}]}
// sorted by path. All or nothing: the new output is built beside the old one (files the last
// manifest lists unchanged are hard links to the old ones, the others copies from the cache, each
// hashed on the way) and switched with it in one step (renameat2 RENAME_EXCHANGE); a run that dies
// or meets a full disk before leaves the old output whole. Files no manifest listed (someone's own)
// and listed files edited by hand are kept; files the last manifest listed that this one does not,
// still holding the listed bytes, are gone. Nothing is written or removed through a symbolic link
// inside the output: a path that would pass through one is an error naming it. Cache bytes that are
// not those recorded are a DamagedArtifact, and nothing is published.
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

/// `artifacts`: (stage id, artifact) of every stage, in run order, on `files`.
void publish_outputs(const fs::path& output, const std::vector<std::pair<std::string, Artifact>>& artifacts,
                     FileSystem& files = real_file_system());

}  // namespace olt
