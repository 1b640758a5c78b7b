#include "olt/cache/lock.h"

#include <algorithm>
#include <chrono>
#include <thread>

namespace olt {

std::optional<CacheLock> CacheLock::unless_stopped(const fs::path& cache_root, const std::string& name,
                                                   const std::function<void()>& on_wait, const std::atomic<bool>& stop,
                                                   bool shared, FileSystem& files) {
  std::optional<CacheLock> held = if_free(cache_root, name, shared, files);
  if (held) return held;
  if (on_wait) on_wait();
  for (std::chrono::milliseconds pause{1};; pause = std::min(2 * pause, std::chrono::milliseconds{50})) {
    if (stop) return std::nullopt;
    std::this_thread::sleep_for(pause);
    if ((held = if_free(cache_root, name, shared, files))) return held;
  }
}

}  // namespace olt
