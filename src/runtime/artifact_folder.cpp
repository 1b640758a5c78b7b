#include "artifact_folder.h"

#include <stdexcept>

#include "olt/core/hash.h"

namespace olt {

void ArtifactFolder::write(const std::string& file, std::string_view bytes) {
  files_.write(dir_ / file, bytes);
  hashed(file, sha256_hex(bytes), bytes.size());
}

void ArtifactFolder::write_pieces(const std::string& file, const std::function<void(const PieceSink&)>& make) {
  Sha256 hash;
  size_t size = 0;
  olt::write_pieces(files_, dir_ / file, [&](const PieceSink& sink) {
    make([&](std::string_view piece) {
      sink(piece);
      hash.update(piece);
      size += piece.size();
    });
  });
  hashed(file, hash.hex(), size);
}

void ArtifactFolder::hashed(const std::string& file, std::string sha256, size_t size) {
  std::lock_guard<std::mutex> lock(mutex_);
  written_.push_back({file, std::move(sha256), size, "", ""});
}

fs::path ArtifactFolder::path(const std::string& file) {
  const fs::path target = dir_ / file;
  files_.make_folders(target.parent_path());
  std::lock_guard<std::mutex> lock(mutex_);
  written_by_libraries_.insert(file);
  return target;
}

std::deque<ArtifactFile> ArtifactFolder::take_described() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::deque<ArtifactFile> out = std::move(referred_);
  for (; !written_.empty(); written_.pop_front())
    if (!written_by_libraries_.count(written_.front().path)) out.push_back(std::move(written_.front()));
  written_by_libraries_.clear();
  return out;
}

void ArtifactFolder::refer(const std::string& file, const Artifact& from, const std::string& from_file) {
  const ArtifactFile* source = from.file(from_file);
  if (!source) throw std::runtime_error("artifact " + from.key + " has no file " + from_file);
  // Referred to where its bytes are (a file `from` itself refers to, at its origin).
  ArtifactFile referred{file, source->sha256, source->size, source->in.empty() ? from.key : source->in,
                        source->in.empty() ? from_file : source->as};
  std::lock_guard<std::mutex> lock(mutex_);
  referred_.push_back(std::move(referred));
}

}  // namespace olt
