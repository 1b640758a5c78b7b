#pragma once
// The output's manifest (olt/runtime/publish.h) and the listing of it kept in the cache: the files a
// publish puts in the output, what the output held before, and the texts that describe them.
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/core/pieces.h"
#include "olt/model/artifact.h"
#include "olt/stages/stage.h"

namespace olt {

/// A file to publish: what the manifest says of it, the stage and the artifact file it comes from.
/// Its path and observation are in its Entries' text, and names many entries share (kind, sensor,
/// stage) point into their Entries' names: ~110 bytes an entry with its path rather than ~170 with
/// strings of its own, and ~270 with a Published.
struct Entry {
  std::string_view path;         ///< in the output folder
  std::string_view observation;  ///< "" when the file does not belong to one
  double timestamp = 0;          ///< of the observation's depth image
  const std::string* kind = nullptr;
  const std::string* sensor = nullptr;  ///< "" when the file does not belong to one sensor
  const std::string* stage = nullptr;
  const Artifact* artifact = nullptr;
  size_t place = 0;  ///< of the file in the artifact's list

  /// In the artifact: its name there, digest and size.
  ListedFile file() const { return artifact->files[place]; }
};

/// The entries sorted by output path (a 10,000-observation job publishes ~80,000: lists parsed an
/// element at a time into blocks that are never copied to grow, sorted in place).
struct Entries {
  Entries() = default;
  Entries(Entries&&) = default;      // the names stay where they are
  Entries(const Entries&) = delete;  // a copy's entries would point into these names
  Entries& operator=(const Entries&) = delete;

  std::deque<Entry> list;
  std::set<std::string, std::less<>> names;  ///< what the entries' kind, sensor and stage point to

  /// `name` kept among the names: one copy however many entries carry it (copied the first time).
  const std::string* name(std::string_view name) {
    const auto found = names.find(name);
    return found != names.end() ? &*found : &*names.emplace(name).first;
  }

  /// A copy of `text` among the entries' texts, where it stays while these entries live.
  std::string_view keep(std::string_view text);

 private:
  static constexpr size_t kBlock = 1 << 20;  ///< bytes; a longer text has a block of its own
  std::vector<std::unique_ptr<char[]>> blocks_;
  size_t used_ = kBlock;  ///< of the last block
};

/// The entry publishing `path`; null when none does.
const Entry* find_entry(const Entries& entries, const std::string& path);

/// Files a manifest lists (path, sha256).
using Listed = std::vector<std::pair<std::string, std::string>>;

/// What the output's manifest lists, sorted by path: each file's path and sha256 as places in one
/// text (80,000 files at 10,000 observations: 8 MB of text and 2.6 MB of places, against 16 MB as
/// pairs of strings).
struct PreviousManifest {
  struct File {
    size_t path, path_size, sha256, sha256_size;  ///< offsets and lengths in `text`
  };
  std::string text;
  std::vector<File> files;

  std::string_view path(const File& f) const { return std::string_view(text).substr(f.path, f.path_size); }
  std::string_view sha256(const File& f) const { return std::string_view(text).substr(f.sha256, f.sha256_size); }
};

/// The digest `previous` lists for `path`; empty when it does not list it.
std::string_view find_listed(const PreviousManifest& previous, std::string_view path);

/// What the manifest at `manifest_file` lists; empty without a manifest OLT can read.
PreviousManifest previous_manifest(const FileSystem& files, const fs::path& manifest_file);

/// The digest of the output's manifest file; empty without one (or one that cannot be read).
std::string manifest_digest(const FileSystem& files, const fs::path& manifest_file);

/// The manifest's text, byte for byte as nlohmann::json's dump(1) of {"files": [...]} writes it,
/// handed to `sink` in pieces of about a megabyte: 31 MB at 80,000 files, hashed and written by a
/// publish without being held whole.
void manifest_pieces(const Entries& entries, const PieceSink& sink);

/// The digest of the manifest listing `entries`.
std::string manifest_digest(const Entries& entries);

/// The listing kept in the cache for the manifest of digest `digest` listing `entries`, in pieces
/// as manifest_pieces: a line with its format ("# olt listing 1"), one with that digest, then a
/// line per file, "<sha256> <bytes in its path> <path>", sorted by path.
void listing_pieces(const std::string& digest, const Entries& entries, const PieceSink& sink);

/// The listing at `file` when it copies the manifest of digest `manifest_digest`; nothing when it is
/// missing, of another manifest, or not one (a listing is only a shortcut: the manifest is read then).
std::optional<PreviousManifest> read_listing(const FileSystem& files, const fs::path& file,
                                             const std::string& manifest_digest);

}  // namespace olt
