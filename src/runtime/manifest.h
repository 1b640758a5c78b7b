#pragma once
// The output's manifest (olt/runtime/publish.h) and the listing of it kept in the cache: the files a
// publish puts in the output, what the output held before, and the texts that describe them.
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/core/pieces.h"
#include "olt/model/artifact.h"
#include "olt/stages/stage.h"

namespace olt {

/// A file to publish, as its Entries hold it: 20 bytes (a 10,000-observation job publishes ~80,000),
/// its path in the entries' text or, where it is its stage's folder and the file's name in its
/// artifact, in their names and the artifact's list; the rest places in their tables, which Entries
/// reads it by.
struct Entry {
  static constexpr uint32_t kInStageFolder = 0xFFFFFFFF;  ///< path_at of a path STAGE/FILE: no place in the text
  uint32_t path_at = 0;                                   ///< in the entries' text
  uint32_t place = 0;                                     ///< of the file in its artifact's list
  uint32_t observation = 0;                               ///< 1 + its place among the entries' observations; 0: none
  uint16_t path_size = 0;
  uint16_t kind = 0, sensor = 0;  ///< places among the entries' names (a file of no sensor: "")
  uint16_t stage = 0;             ///< place among the entries' stages (and their artifacts)
};
static_assert(sizeof(Entry) == 20, "an entry is 20 bytes: 80,000 of them at 10,000 observations");

/// An entry's output path in two parts, `head` then `tail`: its stage's folder ("labels/") and the
/// file's name in its artifact, or "" and the whole path. Compared and measured as the whole.
struct EntryPath {
  std::string_view head, tail;

  size_t size() const { return head.size() + tail.size(); }
  std::string str() const { return std::string(head).append(tail); }
  /// The whole path: `tail` itself where there is no head, else assembled in `scratch`.
  std::string_view in(std::string& scratch) const {
    if (head.empty()) return tail;
    return scratch.assign(head).append(tail);
  }
  /// Below zero, zero or above, as the whole path sorts against `other`'s (bytewise).
  int compare(const EntryPath& other) const;
  bool operator==(const EntryPath& other) const { return size() == other.size() && compare(other) == 0; }
  bool operator!=(const EntryPath& other) const { return !(*this == other); }
  bool operator<(const EntryPath& other) const { return compare(other) < 0; }
};

/// The entries sorted by output path, and what they say of each file: its path, the observation
/// and its timestamp, the manifest kind, the sensor, the stage and its artifact's file. Names many
/// entries share are held once: an observation's files come together in a stage's publish list, and
/// its id and timestamp are kept once for them.
class Entries {
 public:
  Entries() = default;
  Entries(Entries&&) = default;      // the texts stay where they are
  Entries(const Entries&) = delete;  // a copy would be 10 MB at 80,000 files
  Entries& operator=(const Entries&) = delete;

  std::deque<Entry> list;  ///< grown a block at a time, never copied to grow; sorted in place

  /// The stage `stage` whose artifact `artifact` publishes the entries added after (at most 65,535).
  uint16_t add_stage(const std::string& stage, const Artifact& artifact);
  /// Adds a file of the last stage added, the `place`-th in its artifact's list (named p.file); throws
  /// std::length_error for a path or an observation id of 64 KB or more, or past 4 billion files
  /// (places among them are 4 bytes).
  void add(const Published& p, size_t place);

  /// Its output path: 80,000 paths at 10,000 observations, most of them STAGE/FILE, which the
  /// entries do not hold again (2.2 MB).
  EntryPath path(const Entry& e) const {
    if (e.path_at == Entry::kInStageFolder) return {names_[stages_[e.stage].folder], file(e).path};
    return {{}, {blocks_[e.path_at / kBlock].get() + e.path_at % kBlock, e.path_size}};
  }
  std::string_view observation(const Entry& e) const {
    return e.observation ? observations_[e.observation - 1].first : std::string_view();
  }
  double timestamp(const Entry& e) const { return e.observation ? observations_[e.observation - 1].second : 0; }
  const std::string& kind(const Entry& e) const { return names_[e.kind]; }
  const std::string& sensor(const Entry& e) const { return names_[e.sensor]; }
  const std::string& stage(const Entry& e) const { return names_[stages_[e.stage].name]; }
  const Artifact& artifact(const Entry& e) const { return *stages_[e.stage].artifact; }
  /// In the artifact: its name there, digest and size.
  ListedFile file(const Entry& e) const { return artifact(e).files[e.place]; }
  /// Whether `a` goes before `b`: by path, then in the stages' order (their places).
  bool goes_before(const Entry& a, const Entry& b) const {
    if (const int c = path(a).compare(path(b))) return c < 0;
    return a.stage < b.stage;
  }

 private:
  static constexpr uint32_t kBlock = 1 << 20;  ///< bytes of text in a block
  uint16_t name(std::string_view name);
  /// A copy of `text` among the entries' texts, where it stays while these entries live; its place.
  uint32_t keep(std::string_view text);

  std::vector<std::unique_ptr<char[]>> blocks_;
  uint32_t used_ = kBlock;                                         ///< of the last block
  std::vector<std::pair<std::string_view, double>> observations_;  ///< in the texts
  std::deque<std::string> names_;                                  ///< kinds, sensors, stages
  std::map<std::string_view, uint16_t> name_places_;               ///< views of names_
  struct Stage {
    uint16_t name = 0, folder = 0;  ///< places among the names: STAGE, STAGE/
    const Artifact* artifact = nullptr;
  };
  std::vector<Stage> stages_;
};

/// The order that sorts the entries (goes_before), as put_in_order takes it: order[k] is the place in
/// `entries.list` of the entry that goes k-th.
std::vector<uint32_t> sorting_order(const Entries& entries);
/// Puts the entries in `order` (as sorting_order gives one), in place, a cycle of the permutation at a
/// time. `order` must be a permutation of the entries' places (std::invalid_argument otherwise,
/// before any entry moves).
void put_in_order(Entries& entries, const std::vector<uint32_t>& order);
/// Whether the entries are in the order goes_before says (one walk).
bool sorted(const Entries& entries);

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

/// For each of the entries (sorted by path), the place in `previous.files` of the file listed at its
/// path; kNotListed where none is. One walk through both lists (both sorted by path): a binary search
/// per entry and per listed file was a tenth of a publish at 80,000 files. Places of 4 bytes (80,000
/// entries: 320 KB); throws std::length_error for a manifest of 4 billion files or more.
constexpr uint32_t kNotListed = std::numeric_limits<uint32_t>::max();
std::vector<uint32_t> listed_places(const Entries& entries, const PreviousManifest& previous);

/// What the manifest at `manifest_file` lists; empty without a manifest OLT can read.
PreviousManifest previous_manifest(const FileSystem& files, const fs::path& manifest_file);

/// The digest of the output's manifest file; empty without one (or one that cannot be read).
std::string manifest_digest(const FileSystem& files, const fs::path& manifest_file);

/// The manifest's text, byte for byte as nlohmann::json's dump(1) of {"files": [...]} writes it,
/// handed to `sink` in pieces of about a megabyte: 31 MB at 80,000 files, hashed and written by a
/// publish without being held whole (one of at most kManifestHeldBytes is held: manifest_text).
void manifest_pieces(const Entries& entries, const PieceSink& sink);

/// A publish needs the manifest's text twice: hashed, to tell whether the output holds it already,
/// and written where it does not. Made twice, it was 5.2 % of a watch cycle's CPU samples on the
/// synthetic robot (docs/benchmarks.md, "A cycle's fixed part").
struct ManifestText {
  std::string digest;               ///< sha256 hex of the text
  std::optional<std::string> text;  ///< the text, where it is short enough to hold; else none
  /// Hands the text to `sink`: the one held, else made again from `entries`.
  void pieces(const Entries& entries, const PieceSink& sink) const;
};
/// Bytes: the robot's manifest (704 KB) and a TUM job's are held; a 1,000-observation job's (3 MB)
/// and 80,000 files' (31 MB) are made again, so what a long run holds at once does not grow.
constexpr size_t kManifestHeldBytes = size_t{1} << 20;
/// The manifest listing `entries`: its digest, and its text where that is at most `held_bytes`.
ManifestText manifest_text(const Entries& entries, size_t held_bytes = kManifestHeldBytes);

/// The listing kept in the cache for the manifest of digest `digest` listing `entries`, in pieces
/// as manifest_pieces: a line with its format ("# olt listing 1"), one with that digest, then a
/// line per file, "<sha256> <bytes in its path> <path>", sorted by path.
void listing_pieces(const std::string& digest, const Entries& entries, const PieceSink& sink);

/// The listing at `file` when it copies the manifest of digest `manifest_digest`; nothing when it is
/// missing, of another manifest, or not one (a listing is only a shortcut: the manifest is read then).
std::optional<PreviousManifest> read_listing(const FileSystem& files, const fs::path& file,
                                             const std::string& manifest_digest);

}  // namespace olt
