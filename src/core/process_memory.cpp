#include "olt/core/process_memory.h"

#include <sys/stat.h>

#include <atomic>
#include <functional>
#include <list>
#include <mutex>
#include <string>
#include <tuple>
#include <typeindex>
#include <unordered_map>

#include "olt/core/image.h"

namespace olt {
namespace {

// What the keeper keeps: an image file (path, size, modification time in ns, inode, and how it was
// decoded: 0 grey16, 1 colour) or a value kept under a name (the name, zeros, 2).
using Key = std::tuple<std::string, int64_t, int64_t, uint64_t, int>;
constexpr int kNamed = 2;

size_t bytes_of(const cv::Mat& image) { return image.total() * image.elemSize(); }

// Hashed, not ordered: 50,000 names at 10,000 frames, most of them sharing a long beginning (the
// job's path and stage), made an ordered map's lookups compare that beginning 16 times each.
struct KeyHash {
  size_t operator()(const Key& key) const {
    size_t h = std::hash<std::string>()(std::get<0>(key));
    for (const uint64_t part : {static_cast<uint64_t>(std::get<1>(key)), static_cast<uint64_t>(std::get<2>(key)),
                                std::get<3>(key), static_cast<uint64_t>(std::get<4>(key))})
      h = h * 1000003u ^ std::hash<uint64_t>()(part);
    return h;
  }
};

// A value kept, with its type: a shared pointer, not std::any, whose copy for each of 10,000 frames'
// lookups allocated (a shared pointer does not fit its small buffer).
struct Kept {
  Key key;
  std::shared_ptr<const void> value;  // a cv::Mat for an image file
  std::type_index type;
  size_t bytes;
};

struct Keeper {
  std::mutex mutex;
  std::atomic<size_t> budget{0};  // read without the lock: asked for by every frame of every stage
  size_t bytes = 0;
  uint64_t dropped = 0;  // values dropped, or not kept, to stay within the budget (KeptPerItem's items too)
  std::list<Kept> kept;  // most recently read first
  std::unordered_map<Key, std::list<Kept>::iterator, KeyHash> by_key;

  // Under the lock: what is kept under `key`, now the most recently read; null when nothing is.
  const Kept* find(const Key& key) {
    const auto it = by_key.find(key);
    if (it == by_key.end()) return nullptr;
    kept.splice(kept.begin(), kept, it->second);
    return &*it->second;
  }

  // Under the lock: keeps `value` under `key` (replacing what it held), within the budget; a value
  // larger than the whole budget is not kept (it would push out everything else, then itself).
  void keep(const Key& key, std::shared_ptr<const void> value, std::type_index type, size_t value_bytes) {
    if (const auto it = by_key.find(key); it != by_key.end()) {
      bytes -= it->second->bytes;
      kept.erase(it->second);
      by_key.erase(it);
    }
    if (value_bytes > budget) {
      ++dropped;
      return;
    }
    bytes += value_bytes;
    kept.push_front({key, std::move(value), type, value_bytes});
    by_key[key] = kept.begin();
    drop_beyond_budget();
  }

  void drop_beyond_budget() {
    while (bytes > budget && !kept.empty()) {
      bytes -= kept.back().bytes;
      by_key.erase(kept.back().key);
      kept.pop_back();
      ++dropped;
    }
  }
};

Keeper& keeper() {
  static Keeper k;
  return k;
}

cv::Mat remembered(const fs::path& file, bool grey16) {
  const auto decode = [&] { return grey16 ? read_grey16(file) : read_color(file); };
  Keeper& k = keeper();
  if (k.budget == 0) return decode();  // outside the lock: the threads decode their frames side by side
  const auto key_now = [&](Key* key) {
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0) return false;
    *key = {file.string(), st.st_size, static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec,
            st.st_ino, grey16 ? 0 : 1};
    return true;
  };
  Key key;
  if (!key_now(&key)) return decode();  // its error names the file
  {
    const std::lock_guard<std::mutex> lock(k.mutex);
    if (const Kept* found = k.find(key)) return *std::static_pointer_cast<const cv::Mat>(found->value);
  }
  cv::Mat image = decode();  // outside the lock: other threads decode other frames meanwhile
  Key after;
  if (!key_now(&after) || after != key) return image;  // replaced while it was read: not kept
  const std::lock_guard<std::mutex> lock(k.mutex);
  if (k.by_key.count(key)) return image;  // another thread decoded it meanwhile
  k.keep(key, std::make_shared<const cv::Mat>(image), typeid(cv::Mat), bytes_of(image));
  return image;
}

}  // namespace

void keep_in_memory(size_t budget_bytes) {
  Keeper& k = keeper();
  const std::lock_guard<std::mutex> lock(k.mutex);
  k.budget = budget_bytes;
  k.drop_beyond_budget();
}

cv::Mat remembered_grey16(const fs::path& file) { return remembered(file, true); }
cv::Mat remembered_color(const fs::path& file) { return remembered(file, false); }

bool keeping_memory() { return keeper().budget > 0; }

size_t memory_budget() { return keeper().budget; }

KeptMemory kept_memory() {
  Keeper& k = keeper();
  const std::lock_guard<std::mutex> lock(k.mutex);
  return {k.bytes, k.kept.size(), k.dropped};
}

size_t named_value_overhead(const std::string& name) { return 2 * name.size() + 128; }

namespace detail {

void remember_any(const std::string& name, std::shared_ptr<const void> value, std::type_index type, size_t bytes) {
  Keeper& k = keeper();
  const std::lock_guard<std::mutex> lock(k.mutex);
  if (k.budget > 0) k.keep({name, 0, 0, 0, kNamed}, std::move(value), type, bytes + named_value_overhead(name));
}

std::shared_ptr<const void> remembered_any(const std::string& name, std::type_index type, bool take) {
  Keeper& k = keeper();
  if (k.budget == 0) return nullptr;
  Key key{name, 0, 0, 0, kNamed};  // made outside the lock
  const std::lock_guard<std::mutex> lock(k.mutex);
  const auto it = k.by_key.find(key);
  if (it == k.by_key.end() || it->second->type != type) return nullptr;
  if (!take) return k.find(key)->value;
  std::shared_ptr<const void> value = std::move(it->second->value);
  k.bytes -= it->second->bytes;
  k.kept.erase(it->second);
  k.by_key.erase(it);
  return value;
}

void count_not_kept(uint64_t values) {
  if (values == 0) return;
  Keeper& k = keeper();
  const std::lock_guard<std::mutex> lock(k.mutex);
  k.dropped += values;
}

}  // namespace detail

}  // namespace olt
