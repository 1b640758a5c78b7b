#pragma once
// An artifact: the folder of files one stage run (or one frame of it) wrote, as the content store
// keeps it (olt/cache/store.h documents the layout), identified by its key and by the digest of its
// content. Stages read their inputs through it and link files from it.
#include <cstdint>
#include <string>
#include <vector>

#include "olt/core/fs.h"

namespace olt {

struct ArtifactFile {
  std::string path;  ///< relative to the artifact folder, '/'-separated
  std::string sha256;
  uint64_t size = 0;  ///< bytes
};

struct Artifact {
  std::string key;
  std::string digest;
  fs::path dir;
  std::vector<ArtifactFile> files;  ///< sorted by path

  const ArtifactFile* file(const std::string& path) const;
};

}  // namespace olt
