#include "olt/model/artifact.h"

#include <algorithm>

namespace olt {

const std::string& SharedKey::str() const {
  static const std::string none;
  return key_ ? *key_ : none;
}

SharedKey shared_key(SharedKeys& keys, std::string key) {
  auto it = keys.find(std::string_view(key));
  if (it == keys.end()) it = keys.insert(SharedKey(std::move(key))).first;
  return *it;
}

const ArtifactFile* Artifact::file(const std::string& path) const {
  auto it = std::lower_bound(files.begin(), files.end(), path,
                             [](const ArtifactFile& f, const std::string& p) { return f.path < p; });
  return it != files.end() && it->path == path ? &*it : nullptr;
}

fs::path Artifact::path(const std::string& file) const {
  const ArtifactFile* f = this->file(file);
  return f && !f->in.empty() ? artifact_dir(objects, f->in) / f->as : dir / file;
}

fs::path artifact_dir(const fs::path& objects, const std::string& key) { return objects / key.substr(0, 2) / key; }

}  // namespace olt
