#include "artifact_folder.h"

#include <stdexcept>

namespace olt {

void ArtifactFolder::write(const std::string& file, std::string_view bytes) { files_.write(dir_ / file, bytes); }

fs::path ArtifactFolder::path(const std::string& file) {
  const fs::path target = dir_ / file;
  files_.make_folders(target.parent_path());
  return target;
}

void ArtifactFolder::link(const std::string& file, const Artifact& from, const std::string& from_file) {
  const ArtifactFile* source = from.file(from_file);
  if (!source) throw std::runtime_error("artifact " + from.key + " has no file " + from_file);
  files_.link(from.dir / from_file, dir_ / file);
  std::lock_guard<std::mutex> lock(linked_mutex_);
  linked_[file] = source->sha256;
  references_.insert(from.key);
}

}  // namespace olt
