#include "artifact_folder.h"

#include <set>
#include <stdexcept>
#include <utility>

#include "olt/core/hash.h"

namespace olt {
namespace {

// A file's name inside the folder as the store lists it ("a/b.png", not "a//b.png" or "./a/b.png").
std::string listed_name(const std::string& file) { return fs::path(file).lexically_normal().generic_string(); }

}  // namespace

void ArtifactFolder::write(const std::string& file, std::string_view bytes) {
  const std::string sha256 = sha256_hex(bytes);
  if (reuse(file, sha256, bytes.size())) return;
  try {
    files_.write(dir_ / file, bytes);
  } catch (...) {  // what is there now is unknown: the commit hashes it, if it comes to that
    leave_unhashed(file);
    throw;
  }
  record_written(file, sha256, bytes.size());
}

// Refers to the bytes where the stage's last artifact keeps them, if it still does: only for a name
// not written to this folder already (a name is on disk or referred to, never both).
bool ArtifactFolder::reuse(const std::string& file, const std::string& sha256, size_t size) {
  if (!before_) return false;
  const std::string name = listed_name(file);
  const auto kept = before_->find(sha256);
  bool found = kept != before_->end() && kept->second.size == size;
  if (found) {  // looked at outside the lock: a stat of a file no one writes
    const FileStat st = files_.stat(kept->second.path);
    found = st.is_file() && st.size == size;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  const bool on_disk = given_.count(name) && !reused_.count(name);
  given_[name] = sha256;
  if (!found || on_disk) {
    reused_.erase(name);
    return false;
  }
  reused_[name] = &kept->second;
  return true;
}

void ArtifactFolder::write_pieces(const std::string& file, const std::function<void(const PieceSink&)>& make) {
  Sha256 hash;
  size_t size = 0;
  try {
    olt::write_pieces(files_, dir_ / file, [&](const PieceSink& sink) {
      make([&](std::string_view piece) {
        sink(piece);
        hash.update(piece);
        size += piece.size();
      });
    });
  } catch (...) {
    leave_unhashed(file);
    throw;
  }
  record_written(file, hash.hex(), size);
}

void ArtifactFolder::record_written(const std::string& file, const std::string& sha256, size_t size) {
  const std::string name = listed_name(file);
  std::lock_guard<std::mutex> lock(mutex_);
  reused_.erase(name);  // on disk now
  written_.add(name, Digest(sha256), size);
}

void ArtifactFolder::leave_unhashed(const std::string& file) {
  std::string name = listed_name(file);
  std::lock_guard<std::mutex> lock(mutex_);
  reused_.erase(name);  // on disk now
  unhashed_.insert(std::move(name));
}

fs::path ArtifactFolder::path(const std::string& file) {
  const fs::path target = dir_ / file;
  files_.make_folders(target.parent_path());
  leave_unhashed(file);
  return target;
}

ArtifactFiles ArtifactFolder::take_described() {
  std::lock_guard<std::mutex> lock(mutex_);
  ArtifactFiles own = std::exchange(written_, ArtifactFiles());
  own.sort();
  // A file written more than once is left to the commit too: which write came last is the disk's.
  std::set<std::string_view> twice;
  for (size_t i = 1; i < own.size(); ++i)
    if (own[i].path == own[i - 1].path) twice.insert(own[i].path);
  own.erase_if([&](const ListedFile& f) { return twice.count(f.path) || unhashed_.count(f.path); });
  unhashed_.clear();
  ArtifactFiles out = std::exchange(referred_, ArtifactFiles());
  for (const auto& [name, kept] : reused_) out.add(name, Digest(given_.at(name)), kept->size, kept->key, kept->file);
  if (out.size() < own.size()) std::swap(out, own);  // the longer list taken as it is
  for (const ListedFile f : own) out.add(f.path, f.sha256, f.size, f.in, f.as);
  return out;
}

WrittenBefore ArtifactFolder::written(const Artifact& committed) const {
  WrittenBefore kept;
  for (const auto& [name, sha256] : given_) {
    const std::optional<ListedFile> f = committed.file(name);
    if (!f || f->sha256 != sha256) continue;  // written again since, or by a library: not known
    KeptBytes where{f->in.empty() ? committed.key : std::string(f->in), std::string(f->in.empty() ? f->path : f->as),
                    f->size, committed.path(*f)};
    kept.emplace(sha256, std::move(where));
  }
  return kept;
}

void ArtifactFolder::publish(Published published) {
  std::lock_guard<std::mutex> lock(mutex_);
  published_.add(published);
}

void ArtifactFolder::refer(const std::string& file, const Artifact& from, const std::string& from_file) {
  const std::optional<ListedFile> source = from.file(from_file);
  if (!source) throw std::runtime_error("artifact " + from.key + " has no file " + from_file);
  // Referred to where its bytes are (a file `from` itself refers to, at its origin).
  std::lock_guard<std::mutex> lock(mutex_);
  if (source->in.empty())
    referred_.add(file, source->sha256, source->size, from.key, from_file);
  else
    referred_.add(file, source->sha256, source->size, source->in, source->as);
}

}  // namespace olt
