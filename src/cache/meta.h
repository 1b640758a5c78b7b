#pragma once
// What store.cpp and maintenance.cpp share about an artifact's folder (private to the cache).
#include <string>
#include <vector>

#include "olt/cache/store.h"

namespace olt {

inline constexpr const char* kMetaFile = ".artifact.json";

/// An artifact's digest: the SHA-256 of its sorted "sha256  path" lines.
std::string digest_of(const std::vector<ArtifactFile>& files);

/// Whether `key` names a folder under objects/ (and nothing else).
bool safe_key(const std::string& key);

/// Whether a file entry's "in" (a key) and "as" (a relative path without "..") stay inside the store.
bool safe_reference(const std::string& in, const std::string& as);

}  // namespace olt
