#include "written_bytes.h"

#include <mutex>
#include <unordered_map>

#include "olt/core/process_memory.h"

namespace olt {
namespace {

// A full relabel of the robot (320 frames at 640x480) writes about 9 MB, and a one-box edit about
// 3 MB. Larger runs keep what fits and copy the rest from the cache, as a process that keeps
// nothing does.
constexpr size_t kBudget = size_t{32} << 20;

struct Written {
  std::mutex mutex;
  std::unordered_map<std::string, std::shared_ptr<const std::string>> by_digest;
  size_t bytes = 0;
};

Written& written() {
  static Written w;
  return w;
}

}  // namespace

void keep_written(const std::string& sha256, std::string_view bytes) {
  if (!keeping_memory() || bytes.size() > kBudget) return;
  Written& w = written();
  {
    const std::lock_guard<std::mutex> lock(w.mutex);
    if (w.bytes + bytes.size() > kBudget || w.by_digest.count(sha256)) return;
    w.bytes += bytes.size();  // taken before the copy is made, outside the lock
  }
  auto copy = std::make_shared<const std::string>(bytes);
  const std::lock_guard<std::mutex> lock(w.mutex);
  if (!w.by_digest.emplace(sha256, std::move(copy)).second) w.bytes -= bytes.size();
}

size_t written_room() {
  if (!keeping_memory()) return 0;
  Written& w = written();
  const std::lock_guard<std::mutex> lock(w.mutex);
  return kBudget - w.bytes;
}

std::shared_ptr<const std::string> written_bytes(const std::string& sha256) {
  if (!keeping_memory()) return nullptr;
  Written& w = written();
  const std::lock_guard<std::mutex> lock(w.mutex);
  const auto it = w.by_digest.find(sha256);
  return it == w.by_digest.end() ? nullptr : it->second;
}

void forget_written() {
  Written& w = written();
  std::unordered_map<std::string, std::shared_ptr<const std::string>> gone;
  const std::lock_guard<std::mutex> lock(w.mutex);
  gone.swap(w.by_digest);
  w.bytes = 0;
}

}  // namespace olt
