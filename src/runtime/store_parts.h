#pragma once
// The stages' PartStore (frames cached as entries of their own) on the runtime's content store.
#include "olt/cache/store.h"
#include "olt/core/fs.h"
#include "olt/stages/stage.h"

namespace olt {

class StoreParts : public PartStore {
 public:
  explicit StoreParts(const Store& store) : store_(store) {}
  std::optional<Artifact> find(const std::string& key) const override { return store_.find(key); }
  fs::path begin(const std::string& key) const override { return store_.begin(key); }
  Artifact commit(const std::string& key, const fs::path& temp) const override {
    return store_.commit(key, temp, {}, /*durable=*/false);
  }
  void discard(const fs::path& temp) const override { store_.discard(temp); }
  void sync() const override { sync_file_system(store_.root()); }

 private:
  const Store& store_;
};

}  // namespace olt
