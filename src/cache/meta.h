#pragma once
// What store.cpp and maintenance.cpp share about an artifact's folder (private to the cache).
#include <optional>
#include <string>
#include <vector>

#include "olt/cache/store.h"

namespace olt {

inline constexpr const char* kMetaFile = ".artifact.json";

/// An artifact's digest: the SHA-256 of its sorted "sha256  path" lines.
std::string digest_of(const ArtifactFiles& files);

/// What an artifact's .artifact.json says.
struct Meta {
  std::string key, digest;
  ArtifactFiles files;
};

/// The metadata in `text`, read as parser events (the labeling stage's lists 70,000 files); nullopt
/// when it is not JSON, lacks its digest or files, or a file entry lacks its path, sha256 or size or
/// holds another type there (members it does not know are skipped).
std::optional<Meta> read_meta(const std::string& text);

/// read_meta of a file, parsed as it is read (the labeling stage's metadata: 18 MB at 10,000 frames,
/// not held whole); errors as FileSystem::read_stream.
std::optional<Meta> read_meta_file(const FileSystem& files, const fs::path& file);

/// Whether `key` names a folder under objects/ (and nothing else).
bool safe_key(std::string_view key);

/// Whether a file entry's "in" (a key) and "as" (a relative path without "..") stay inside the store.
bool safe_reference(std::string_view in, std::string_view as);

}  // namespace olt
