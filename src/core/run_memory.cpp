#include "olt/core/run_memory.h"

#include <map>
#include <mutex>
#include <utility>

#include "olt/core/process_memory.h"

namespace olt {
namespace {

struct RunMemory {
  std::mutex mutex;
  std::map<std::pair<std::string, std::type_index>, std::shared_ptr<const void>> kept;
  size_t bytes = 0;
};

RunMemory& run_memory() {
  static RunMemory memory;
  return memory;
}

}  // namespace

namespace detail {

void keep_for_run_any(const std::string& sha256, std::type_index type, std::shared_ptr<const void> value,
                      size_t bytes) {
  if (!keeping_memory()) return;
  RunMemory& m = run_memory();
  const std::lock_guard<std::mutex> lock(m.mutex);
  const size_t taken = bytes + kRunMemoryEntryBytes;
  if (taken > kRunMemoryBudget - m.bytes) return;
  if (m.kept.emplace(std::pair(sha256, type), std::move(value)).second) m.bytes += taken;
}

std::shared_ptr<const void> kept_for_run_any(const std::string& sha256, std::type_index type) {
  if (!keeping_memory()) return nullptr;
  RunMemory& m = run_memory();
  const std::lock_guard<std::mutex> lock(m.mutex);
  const auto it = m.kept.find(std::pair(sha256, type));
  return it == m.kept.end() ? nullptr : it->second;
}

}  // namespace detail

size_t run_memory_room() {
  if (!keeping_memory()) return 0;
  RunMemory& m = run_memory();
  const std::lock_guard<std::mutex> lock(m.mutex);
  return kRunMemoryBudget - m.bytes;
}

void forget_run_memory() {
  RunMemory& m = run_memory();
  decltype(m.kept) gone;  // freed after the lock is let go
  const std::lock_guard<std::mutex> lock(m.mutex);
  gone.swap(m.kept);
  m.bytes = 0;
}

}  // namespace olt
