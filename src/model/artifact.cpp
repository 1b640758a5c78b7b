#include "olt/model/artifact.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace olt {

void ArtifactFiles::add(std::string_view path, const Digest& sha256, uint64_t size, std::string_view in,
                        std::string_view as) {
  constexpr size_t longest = std::numeric_limits<uint16_t>::max();
  if (path.size() > longest || as.size() > longest || in.size() > longest ||
      names_.size() + path.size() + as.size() + in.size() > UINT32_MAX)
    throw std::length_error("artifact file name too long (64 KB or more): " + std::string(path.substr(0, 200)) +
                            (in.empty() ? "" : " in " + std::string(in.substr(0, 200))));
  Entry e;
  e.sha256 = sha256;
  e.size = size;
  e.path_at = add_name(path);
  e.path_length = static_cast<uint16_t>(path.size());
  e.in = add_once(in);
  e.as = add_once(as);
  entries_.push_back(e);
}

uint32_t ArtifactFiles::add_name(std::string_view name) {
  const auto at = static_cast<uint32_t>(names_.size());
  names_.insert(names_.end(), name.begin(), name.end());
  return at;
}

uint32_t ArtifactFiles::add_once(std::string_view name) {
  if (name.empty()) return 0;
  const std::hash<std::string_view> hash;
  if (once_places_.empty())  // let go by sort(): made again from once_
    for (size_t k = 0; k < once_.size(); ++k)
      once_places_.emplace(hash(this->name(once_[k].first, once_[k].second)), static_cast<uint32_t>(k + 1));
  const size_t h = hash(name);
  const auto [first, last] = once_places_.equal_range(h);
  for (auto it = first; it != last; ++it)
    if (this->name(it->second) == name) return it->second;
  once_.emplace_back(add_name(name), static_cast<uint16_t>(name.size()));
  once_places_.emplace(h, static_cast<uint32_t>(once_.size()));
  return static_cast<uint32_t>(once_.size());
}

void ArtifactFiles::sort() {
  const auto by_path = [&](const Entry& a, const Entry& b) { return path_of(a) < path_of(b); };
  if (!std::is_sorted(entries_.begin(), entries_.end(), by_path)) std::sort(entries_.begin(), entries_.end(), by_path);
  decltype(once_places_)().swap(once_places_);  // its buckets too
  names_.shrink_to_fit();
  entries_.shrink_to_fit();
  once_.shrink_to_fit();
}

ArtifactFiles ArtifactFiles::only(const FileFilter& keep) const {
  ArtifactFiles kept;
  for (const ListedFile f : *this)
    if (keep(f)) kept.add(f.path, f.sha256, f.size, f.in, f.as);
  kept.sort();
  return kept;
}

ListedFile ArtifactFiles::operator[](size_t i) const {
  const Entry& e = entries_[i];
  return {path_of(e), e.sha256, e.size, name(e.in), name(e.as)};
}

std::optional<size_t> ArtifactFiles::place(std::string_view path) const {
  auto it = std::lower_bound(entries_.begin(), entries_.end(), path,
                             [&](const Entry& e, std::string_view p) { return path_of(e) < p; });
  if (it == entries_.end() || path_of(*it) != path) return std::nullopt;
  return static_cast<size_t>(it - entries_.begin());
}

std::optional<ListedFile> ArtifactFiles::find(std::string_view path) const {
  const std::optional<size_t> i = place(path);
  return i ? std::optional<ListedFile>((*this)[*i]) : std::nullopt;
}

size_t ArtifactFiles::bytes() const {
  return entries_.capacity() * sizeof(Entry) + names_.capacity() + once_.capacity() * sizeof(Name);
}

fs::path Artifact::path(const std::string& file) const {
  const std::optional<ListedFile> f = this->file(file);
  return f ? path(*f) : dir / file;
}

fs::path Artifact::path(const ListedFile& file) const {
  return file.in.empty() ? dir / file.path : artifact_dir(objects, file.in) / file.as;
}

fs::path artifact_dir(const fs::path& objects, std::string_view key) { return objects / key.substr(0, 2) / key; }

}  // namespace olt
