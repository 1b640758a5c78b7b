#pragma once
// The output's manifest (olt/runtime/publish.h) and the listing of it kept in the cache: the files a
// publish puts in the output, what the output held before, and the texts that describe them.
#include <deque>
#include <functional>
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

/// A file to publish: what the manifest says of it, the stage and the artifact file it comes from.
struct Entry {
  Published published;
  std::string stage;
  const Artifact* artifact;
  const ArtifactFile* file;
};

/// The entries sorted by output path (a 10,000-observation job publishes ~80,000: lists parsed an
/// element at a time into blocks that are never copied to grow, sorted in place).
using Entries = std::deque<Entry>;

/// The entry publishing `path`; null when none does.
const Entry* find_entry(const Entries& entries, const std::string& path);

/// What the output's manifest lists (path -> sha256), sorted by path.
using Listed = std::vector<std::pair<std::string, std::string>>;

/// The digest `listed` gives `path`; null when it does not list it.
const std::string* find_listed(const Listed& listed, const std::string& path);

/// What the manifest at `manifest_file` lists; empty without a manifest OLT can read.
Listed previous_manifest(const FileSystem& files, const fs::path& manifest_file);

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
std::optional<Listed> read_listing(const FileSystem& files, const fs::path& file, const std::string& manifest_digest);

}  // namespace olt
