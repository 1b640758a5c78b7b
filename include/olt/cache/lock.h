#pragma once
// A lock shared by every process using one cache folder, such as shards of a cluster job on a
// shared file system: flock(2) on a file under CACHE/locks/ (FileSystem::lock). The kernel releases
// it when its holder exits or dies, so a killed shard never leaves a lock behind. On NFS, Linux maps
// flock to the server's byte-range locks, which are released the same way.
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "olt/core/file_system.h"

namespace olt {

class CacheLock {
 public:
  /// Blocks until `name`'s lock under `cache_root` is held: exclusively, or `shared` with other
  /// shared holders (runs share the "gc" lock; `olt cache gc` takes it exclusively). `on_wait` is
  /// called once, before blocking, when another process holds it.
  CacheLock(const fs::path& cache_root, const std::string& name, const std::function<void()>& on_wait,
            bool shared = false, FileSystem& files = real_file_system())
      : lock_(files.lock(path(cache_root, name), shared, on_wait, nullptr)) {}

  /// As the constructor, but the wait ends when `stop` is set (olt run's SIGINT or SIGTERM): nothing
  /// then. It waits by trying again (retry_until_stopped), so it takes the lock at most 250 ms after
  /// it is free and sees a stop as soon.
  static std::optional<CacheLock> unless_stopped(const fs::path& cache_root, const std::string& name,
                                                 const std::function<void()>& on_wait, const std::atomic<bool>& stop,
                                                 bool shared = false, FileSystem& files = real_file_system()) {
    std::unique_ptr<FileSystem::Lock> lock = files.lock(path(cache_root, name), shared, on_wait, &stop);
    if (!lock) return std::nullopt;
    return CacheLock(std::move(lock));
  }

  /// The lock if no other process holds it now; nothing when one does (never waits).
  static std::optional<CacheLock> if_free(const fs::path& cache_root, const std::string& name, bool shared = false,
                                          FileSystem& files = real_file_system()) {
    std::unique_ptr<FileSystem::Lock> lock = files.try_lock(path(cache_root, name), shared);
    if (!lock) return std::nullopt;
    return CacheLock(std::move(lock));
  }

 private:
  explicit CacheLock(std::unique_ptr<FileSystem::Lock> lock) : lock_(std::move(lock)) {}
  static fs::path path(const fs::path& cache_root, const std::string& name) {
    return cache_root / "locks" / (name + ".lock");
  }

  std::unique_ptr<FileSystem::Lock> lock_;
};

}  // namespace olt
