#pragma once
// Publishing stage outputs into the output folder, and OUTPUT/manifest.json:
//   {"files": [{"path", "sha256", "kind", "stage", "sensor"?, "observation"?: {"id", "timestamp"}}]}
// sorted by path. Each file is copied from its cache artifact through a temporary file and a rename;
// files the previous manifest listed and this one does not are removed, where they still hold the
// bytes it listed (a file someone edited stays); the manifest is written last, so it never lists a
// file that is not there. Nothing is written or removed through a symbolic link inside the output:
// a path that would pass through one is an error naming it. Each file copied is hashed on the way:
// cache bytes that are not those recorded are a DamagedArtifact, not a published file.
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

/// `artifacts`: (stage id, artifact) of every stage, in run order, on `files`. Returns the manifest.
nlohmann::json publish_outputs(const fs::path& output, const std::vector<std::pair<std::string, Artifact>>& artifacts,
                               FileSystem& files = real_file_system());

}  // namespace olt
