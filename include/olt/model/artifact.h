#pragma once
// An artifact: the files one stage run (or one frame of it) wrote, as the content store keeps it
// (olt/cache/store.h documents the layout), identified by its key and by the digest of its content.
// Stages read their inputs through it and take files from it. A file is the artifact's own (in its
// folder) or another artifact's, referred to without a copy or a link: a stage with units lists its
// frames' files that way, so an edit that relabels 49 frames writes 49 frames' files, not 320.
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "olt/core/page_allocator.h"

namespace olt {

/// A file of an artifact as a stage's writer describes it, or a test builds it.
struct ArtifactFile {
  std::string path;  ///< relative to the artifact folder, '/'-separated
  Digest sha256;
  uint64_t size = 0;  ///< bytes
  std::string in;     ///< the key of the artifact holding the bytes when it is another one, else ""
  std::string as;     ///< ... and the file's path there
};

/// One of an artifact's files as its list holds it: a view, valid while the list lives and nothing
/// is added to it or sorted.
struct ListedFile {
  std::string_view path;
  Digest sha256;
  uint64_t size = 0;
  std::string_view in;  ///< "" when the bytes are the artifact's own
  std::string_view as;
};

/// Which of an artifact's files a reader keeps of its list (a stage that looks up only a few).
using FileFilter = std::function<bool(const ListedFile&)>;

/// A file the artifact refers to in another one: what Artifact::path cannot find without the list
/// (a file the list does not hold is taken to be the artifact's own, in its folder).
inline bool referred_file(const ListedFile& f) { return !f.in.empty(); }

/// An artifact's files, held in a few blocks: an entry of 56 bytes each and one text of their
/// names (a stage's artifact lists 70,000 at 10,000 frames; as ArtifactFile structs, with a string
/// and a heap block for each name, they took 2.5 times as much and were scattered among what a stage
/// frees, which then stayed with the process). The artifacts referred to, and the names files have
/// there, are each held once: a frame's seven files name one entry, and 70,000 files a handful of
/// names.
class ArtifactFiles {
 public:
  ArtifactFiles() = default;
  ArtifactFiles(std::initializer_list<ArtifactFile> files) {  // NOLINT(google-explicit-constructor): a list
    for (const ArtifactFile& f : files) add(f);
  }
  void reserve(size_t files) { entries_.reserve(files); }
  size_t capacity() const { return entries_.capacity(); }
  /// `path`, `in` and `as` must not be views into this list (its names may move); throws
  /// std::length_error for a name of 64 KB or more.
  void add(std::string_view path, const Digest& sha256, uint64_t size, std::string_view in = {},
           std::string_view as = {});
  void add(const ArtifactFile& f) { add(f.path, f.sha256, f.size, f.in, f.as); }
  /// Sorts by path, as find needs them, and trims what adding needed (spare capacity, the index of
  /// the names held once): for when the adding is done.
  void sort();
  /// Removes the files `drop` is true of (their names stay in the text, unused).
  template <typename Drop>
  void erase_if(Drop drop) {
    size_t kept = 0;
    for (size_t i = 0; i < entries_.size(); ++i)
      if (!drop((*this)[i])) entries_[kept++] = entries_[i];
    entries_.resize(kept);
  }
  /// A list of the files `keep` is true of, holding only their names; sorted as this one.
  ArtifactFiles only(const FileFilter& keep) const;
  /// The file at `path` of a sorted list, and its place there.
  std::optional<ListedFile> find(std::string_view path) const;
  std::optional<size_t> place(std::string_view path) const;

  size_t size() const { return entries_.size(); }
  bool empty() const { return entries_.empty(); }
  ListedFile operator[](size_t i) const;
  /// What the list holds, bytes.
  size_t bytes() const;

  class const_iterator {
   public:
    using iterator_category = std::input_iterator_tag;  // it yields values, not references
    using value_type = ListedFile;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = ListedFile;
    const_iterator(const ArtifactFiles* list, size_t i) : list_(list), i_(i) {}
    ListedFile operator*() const { return (*list_)[i_]; }
    const_iterator& operator++() { return ++i_, *this; }
    bool operator==(const const_iterator& o) const { return i_ == o.i_; }
    bool operator!=(const const_iterator& o) const { return i_ != o.i_; }

   private:
    const ArtifactFiles* list_;
    size_t i_;
  };
  const_iterator begin() const { return {this, 0}; }
  const_iterator end() const { return {this, entries_.size()}; }

 private:
  struct Entry {
    uint64_t size = 0;
    Digest sha256;
    uint16_t path_length = 0;
    uint32_t path_at = 0;     ///< in names_
    uint32_t in = 0, as = 0;  ///< 1 + its place in once_; 0: none
  };
  static_assert(sizeof(Entry) == 56, "an entry is 56 bytes: 70,000 of them at 10,000 frames");
  using Name = std::pair<uint32_t, uint16_t>;  ///< where a name is in names_, and its length
  std::string_view name(uint32_t at, uint16_t length) const { return {names_.data() + at, length}; }
  std::string_view name(uint32_t once) const {
    return once ? name(once_[once - 1].first, once_[once - 1].second) : std::string_view();
  }
  uint32_t add_name(std::string_view name);
  uint32_t add_once(std::string_view name);
  std::string_view path_of(const Entry& e) const { return name(e.path_at, e.path_length); }

  std::vector<Entry, PageAllocator<Entry>> entries_;
  std::vector<char, PageAllocator<char>> names_;
  /// The names held once: the keys of the artifacts referred to and the files' names there.
  std::vector<Name, PageAllocator<Name>> once_;
  /// Into once_ (1 + the place), by the name's hash, while adding: 10,000 frames' keys, each
  /// compared a dozen times in an ordered map.
  std::unordered_multimap<size_t, uint32_t> once_places_;
};

struct Artifact {
  std::string key;
  std::string digest;
  fs::path dir;
  ArtifactFiles files;  ///< sorted by path
  fs::path objects;     ///< the store's folder of artifacts, where the referred ones are

  std::optional<ListedFile> file(std::string_view path) const { return files.find(path); }
  /// Where the bytes of `file` are: in this artifact's folder, or in the artifact it refers to.
  fs::path path(const std::string& file) const;
  fs::path path(const ListedFile& file) const;
};

/// The folder of the artifact `key` in a store's folder of artifacts: objects/<k0k1>/<key>.
fs::path artifact_dir(const fs::path& objects, std::string_view key);

}  // namespace olt
