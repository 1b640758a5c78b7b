#include "artifact_folder.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "olt/core/hash.h"
#include "olt/core/run_memory.h"

namespace olt {
namespace {

// A file's name inside the folder as the store lists it ("a/b.png", not "a//b.png" or "./a/b.png"):
// the name a stage gives is one already, but for a few (normalised as a path, each write of a file
// cost a path made twice).
std::string listed_name(const std::string& file) {
  return already_normal(file) ? file : fs::path(file).lexically_normal().generic_string();
}

// The largest file whose bytes are kept for publishing (run_memory.h): a larger one (the COCO file
// at 10,000 observations, 15 MB, written a megabyte at a time) is copied from the cache, as in a
// process that keeps nothing, rather than held whole.
constexpr size_t kKeptFileBytes = size_t{4} << 20;

// Keeps `bytes`, written under `sha256`, for publishing, where they are kept at all and fit.
void keep_for_publishing(const std::string& sha256, std::string bytes) {
  const size_t size = bytes.size();
  bytes.shrink_to_fit();  // made of pieces, it may have room for twice as many
  if (size <= kKeptFileBytes)
    keep_for_run<std::string>(sha256, std::make_shared<const std::string>(std::move(bytes)), size);
}

// Where the bytes of `f`, listed as `path` by the artifact `key`, are: that artifact's own file, or the
// one it refers to (entry, name there).
std::pair<std::string_view, std::string_view> origin(const ListedFile& f, std::string_view key, std::string_view path) {
  return referred_file(f) ? std::pair{f.in, f.as} : std::pair{key, path};
}

}  // namespace

void ArtifactFolder::write(const std::string& file, std::string_view bytes) {
  const std::string sha256 = sha256_hex(bytes);
  if (carrying_ && carried(listed_name(file), Digest(sha256), bytes.size())) return;  // olt run: neither
  try {
    files_.write(dir_ / file, bytes);
  } catch (...) {  // what is there now is unknown: the commit hashes it, if it comes to that
    leave_unhashed(file);
    throw;
  }
  record_written(file, sha256, bytes.size());
  if (std::min(kKeptFileBytes, run_memory_room()) >= bytes.size()) keep_for_publishing(sha256, std::string(bytes));
}

bool ArtifactFolder::carried(const std::string& file, const Digest& sha256, size_t size) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::optional<ListedFile> before = before_.find(file);
  if (named_.count(file) || !before || before->sha256 != sha256 || before->size != size) {
    name_written(file);
    return false;
  }
  referred_.add(file, sha256, size, before->in, before->as);
  named_[file] = true;
  return true;
}

void ArtifactFolder::name_written(const std::string& file) {
  if (!carrying_) return;
  auto [it, first] = named_.emplace(file, false);
  if (!first && it->second) uncarried_.insert(file);
  it->second = false;
}

void ArtifactFolder::carry_from(ArtifactFiles before) {
  before.sort();
  std::lock_guard<std::mutex> lock(mutex_);
  carrying_ = true;
  before_ = std::move(before);
}

ArtifactFiles ArtifactFolder::carried_forward(const Artifact& committed) const {
  ArtifactFiles out;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [name, was_carried] : named_) {
    const std::optional<ListedFile> f = committed.file(name);
    if (!f || f->sha256.empty()) continue;
    const auto [in, as] = origin(*f, committed.key, name);
    out.add(name, f->sha256, f->size, in, as);
  }
  out.sort();
  return out;
}

void ArtifactFolder::write_pieces(const std::string& file, const std::function<void(const PieceSink&)>& make) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    name_written(listed_name(file));
  }
  Sha256 hash;
  size_t size = 0;
  const size_t room = std::min(kKeptFileBytes, run_memory_room());
  std::string kept;  // the bytes, for publishing, while they fit the room
  try {
    olt::write_pieces(files_, dir_ / file, [&](const PieceSink& sink) {
      make([&](std::string_view piece) {
        sink(piece);
        hash.update(piece);
        size += piece.size();
        if (size <= room)
          kept.append(piece);
        else if (!kept.empty())
          std::string().swap(kept);  // too large to keep: let go at once
      });
    });
  } catch (...) {
    leave_unhashed(file);
    throw;
  }
  const std::string sha256 = hash.hex();
  record_written(file, sha256, size);
  if (size <= room) keep_for_publishing(sha256, std::move(kept));
}

void ArtifactFolder::record_written(const std::string& file, const std::string& sha256, size_t size) {
  const std::string name = listed_name(file);
  std::lock_guard<std::mutex> lock(mutex_);
  written_.add(name, Digest(sha256), size);
}

void ArtifactFolder::leave_unhashed(const std::string& file) {
  std::string name = listed_name(file);
  std::lock_guard<std::mutex> lock(mutex_);
  name_written(name);
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
  if (!uncarried_.empty()) out.erase_if([&](const ListedFile& f) { return uncarried_.count(f.path) > 0; });
  if (out.size() < own.size()) std::swap(out, own);  // the longer list taken as it is
  for (const ListedFile f : own) out.add(f.path, f.sha256, f.size, f.in, f.as);
  return out;
}

void ArtifactFolder::publish(Published published) {
  std::lock_guard<std::mutex> lock(mutex_);
  published_.add(published);
}

void ArtifactFolder::refer(const std::string& file, const Artifact& from, const std::string& from_file) {
  const std::optional<ListedFile> source = from.file(from_file);
  if (!source) throw std::runtime_error("artifact " + from.key + " has no file " + from_file);
  // Referred to where its bytes are (a file `from` itself refers to, at its origin).
  const auto [in, as] = origin(*source, from.key, from_file);
  std::lock_guard<std::mutex> lock(mutex_);
  referred_.add(file, source->sha256, source->size, in, as);
}

}  // namespace olt
