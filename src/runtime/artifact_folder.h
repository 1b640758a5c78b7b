#pragma once
// The stages' ArtifactWriter on a folder of the content store: the files a stage writes and links,
// what it publishes, and which other artifacts its linked files come from (private to the runtime).
// Its files go through the store's FileSystem; `path()` (for libraries that write files themselves)
// is meaningful on the real one only.
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/stages/stage.h"

namespace olt {

class ArtifactFolder : public ArtifactWriter {
 public:
  ArtifactFolder(fs::path dir, FileSystem& files) : dir_(std::move(dir)), files_(files) {}
  void write(const std::string& file, std::string_view bytes) override;
  fs::path path(const std::string& file) override;
  void link(const std::string& file, const Artifact& from, const std::string& from_file) override;
  void publish(Published published) override { published_.push_back(std::move(published)); }
  using ArtifactWriter::publish;

  const fs::path& dir() const { return dir_; }
  const std::vector<Published>& published() const { return published_; }
  /// Files linked from other artifacts: path -> sha256 (known, so not hashed again on commit).
  const std::map<std::string, std::string>& linked() const { return linked_; }
  /// Keys of the artifacts files were linked from.
  const std::set<std::string>& references() const { return references_; }

 private:
  fs::path dir_;
  FileSystem& files_;
  std::vector<Published> published_;
  std::map<std::string, std::string> linked_;
  std::set<std::string> references_;
  std::mutex linked_mutex_;
};

}  // namespace olt
