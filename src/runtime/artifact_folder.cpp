#include "artifact_folder.h"

#include <stdexcept>

namespace olt {

void ArtifactFolder::write(const std::string& file, std::string_view bytes) { files_.write(dir_ / file, bytes); }

fs::path ArtifactFolder::path(const std::string& file) {
  const fs::path target = dir_ / file;
  files_.make_folders(target.parent_path());
  return target;
}

void ArtifactFolder::refer(const std::string& file, const Artifact& from, const std::string& from_file) {
  const ArtifactFile* source = from.file(from_file);
  if (!source) throw std::runtime_error("artifact " + from.key + " has no file " + from_file);
  // Referred to where its bytes are (a file `from` itself refers to, at its origin).
  ArtifactFile referred{file, source->sha256, source->size, source->in.empty() ? from.key : source->in,
                        source->in.empty() ? from_file : source->as};
  std::lock_guard<std::mutex> lock(referred_mutex_);
  referred_.push_back(std::move(referred));
}

}  // namespace olt
