#pragma once
// An artifact: the files one stage run (or one frame of it) wrote, as the content store keeps it
// (olt/cache/store.h documents the layout), identified by its key and by the digest of its content.
// Stages read their inputs through it and take files from it. A file is the artifact's own (in its
// folder) or another artifact's, referred to without a copy or a link: a stage with units lists its
// frames' files that way, so an edit that relabels 49 frames writes 49 frames' files, not 320.
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "olt/core/fs.h"
#include "olt/core/hash.h"

namespace olt {

/// An artifact's key as the files that refer to it carry it: one copy shared by all (a labeling
/// stage's 70,000 files refer to 10,000 frame entries: seven files a key). Made from a string it is
/// a copy of its own; copied from another, it shares that one's. Immutable.
class SharedKey {
 public:
  SharedKey() = default;
  SharedKey(std::string key)  // NOLINT(google-explicit-constructor): a key is a string
      : key_(key.empty() ? nullptr : std::make_shared<const std::string>(std::move(key))) {}
  SharedKey(const char* key) : SharedKey(std::string(key)) {}  // NOLINT(google-explicit-constructor)
  operator const std::string&() const { return str(); }        // NOLINT(google-explicit-constructor)
  const std::string& str() const;
  bool empty() const { return !key_; }
  friend bool operator==(const SharedKey& a, std::string_view b) { return a.str() == b; }
  friend bool operator!=(const SharedKey& a, std::string_view b) { return a.str() != b; }

  /// By text, found by text without a copy (std::set's transparent lookup).
  struct Order {
    using is_transparent = void;
    bool operator()(const SharedKey& a, const SharedKey& b) const { return a.str() < b.str(); }
    bool operator()(const SharedKey& a, std::string_view b) const { return a.str() < b; }
    bool operator()(std::string_view a, const SharedKey& b) const { return a < b.str(); }
  };

 private:
  std::shared_ptr<const std::string> key_;
};

/// The keys met so far, one SharedKey each.
using SharedKeys = std::set<SharedKey, SharedKey::Order>;

/// `key` as `keys` holds it, added the first time.
SharedKey shared_key(SharedKeys& keys, std::string key);

struct ArtifactFile {
  std::string path;  ///< relative to the artifact folder, '/'-separated
  Digest sha256;
  uint64_t size = 0;  ///< bytes
  SharedKey in;       ///< the key of the artifact holding the bytes when it is another one, else ""
  std::string as;     ///< ... and the file's path there
};

struct Artifact {
  std::string key;
  std::string digest;
  fs::path dir;
  std::vector<ArtifactFile> files;  ///< sorted by path
  fs::path objects;                 ///< the store's folder of artifacts, where the referred ones are

  const ArtifactFile* file(const std::string& path) const;
  /// Where the bytes of `file` are: in this artifact's folder, or in the artifact it refers to.
  fs::path path(const std::string& file) const;
};

/// The folder of the artifact `key` in a store's folder of artifacts: objects/<k0k1>/<key>.
fs::path artifact_dir(const fs::path& objects, const std::string& key);

}  // namespace olt
