#pragma once
// A lock shared by every process using one cache folder, such as shards of a cluster job on a
// shared file system: flock(2) on a file under CACHE/locks/. The kernel releases it when its holder
// exits or dies, so a killed shard never leaves a lock behind. On NFS, Linux maps flock to the
// server's byte-range locks, which are released the same way.
#include <filesystem>
#include <functional>
#include <string>

namespace olt {

class CacheLock {
 public:
  /// Blocks until `name`'s lock under `cache_root` is held: exclusively, or `shared` with other
  /// shared holders (runs share the "gc" lock; `olt cache gc` takes it exclusively). `on_wait` is
  /// called once, before blocking, when another process holds it.
  CacheLock(const std::filesystem::path& cache_root, const std::string& name, const std::function<void()>& on_wait,
            bool shared = false);
  ~CacheLock();
  CacheLock(const CacheLock&) = delete;
  CacheLock& operator=(const CacheLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace olt
