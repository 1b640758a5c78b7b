#include "artifact_folder.h"

#include <stdexcept>

namespace olt {

void ArtifactFolder::write(const std::string& file, std::string_view bytes) { write_file(dir_ / file, bytes); }

fs::path ArtifactFolder::path(const std::string& file) {
  const fs::path target = dir_ / file;
  fs::create_directories(target.parent_path());
  return target;
}

void ArtifactFolder::link(const std::string& file, const Artifact& from, const std::string& from_file) {
  const ArtifactFile* source = from.file(from_file);
  if (!source) throw std::runtime_error("artifact " + from.key + " has no file " + from_file);
  const fs::path target = path(file);
  std::error_code ec;
  fs::create_hard_link(from.dir / from_file, target, ec);
  if (ec) fs::copy_file(from.dir / from_file, target, fs::copy_options::overwrite_existing);
  std::lock_guard<std::mutex> lock(linked_mutex_);
  linked_[file] = source->sha256;
  references_.insert(from.key);
}

}  // namespace olt
