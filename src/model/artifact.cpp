#include "olt/model/artifact.h"

#include <algorithm>

namespace olt {

const ArtifactFile* Artifact::file(const std::string& path) const {
  auto it = std::lower_bound(files.begin(), files.end(), path,
                             [](const ArtifactFile& f, const std::string& p) { return f.path < p; });
  return it != files.end() && it->path == path ? &*it : nullptr;
}

}  // namespace olt
