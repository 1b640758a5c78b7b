#include "olt/core/decoded_images.h"

#include <sys/stat.h>

#include <list>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "olt/core/image.h"

namespace olt {
namespace {

// What the keeper keeps: an image file (path, size, modification time in ns, inode, and how it was
// decoded: 0 grey16, 1 colour) or images kept under a name (the name, zeros, 2).
using Key = std::tuple<std::string, int64_t, int64_t, uint64_t, int>;
constexpr int kNamed = 2;

size_t bytes_of(const std::vector<cv::Mat>& images) {
  size_t bytes = 0;
  for (const auto& image : images) bytes += image.total() * image.elemSize();
  return bytes;
}

struct Keeper {
  std::mutex mutex;
  size_t budget = 0, bytes = 0;
  std::list<std::pair<Key, std::vector<cv::Mat>>> images;  // most recently read first
  std::map<Key, std::list<std::pair<Key, std::vector<cv::Mat>>>::iterator> by_key;

  // Under the lock: the images kept under `key`, now the most recently read; none.
  std::optional<std::vector<cv::Mat>> find(const Key& key) {
    const auto it = by_key.find(key);
    if (it == by_key.end()) return std::nullopt;
    images.splice(images.begin(), images, it->second);
    return it->second->second;
  }

  // Under the lock: keeps `kept` under `key` (replacing what it held), within the budget.
  void keep(const Key& key, std::vector<cv::Mat> kept) {
    if (const auto it = by_key.find(key); it != by_key.end()) {
      bytes -= bytes_of(it->second->second);
      images.erase(it->second);
    }
    bytes += bytes_of(kept);
    images.emplace_front(key, std::move(kept));
    by_key[key] = images.begin();
    drop_beyond_budget();
  }

  void drop_beyond_budget() {
    while (bytes > budget && !images.empty()) {
      bytes -= bytes_of(images.back().second);
      by_key.erase(images.back().first);
      images.pop_back();
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
  size_t budget = 0;
  {
    const std::lock_guard<std::mutex> lock(k.mutex);
    budget = k.budget;
  }
  if (budget == 0) return decode();  // outside the lock: the threads decode their frames side by side
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
    if (auto found = k.find(key)) return found->front();
  }
  cv::Mat image = decode();  // outside the lock: other threads decode other frames meanwhile
  Key after;
  if (!key_now(&after) || after != key) return image;  // replaced while it was read: not kept
  const std::lock_guard<std::mutex> lock(k.mutex);
  if (k.by_key.count(key)) return image;  // another thread decoded it meanwhile
  k.keep(key, {image});
  return image;
}

}  // namespace

void keep_decoded_images(size_t budget_bytes) {
  Keeper& k = keeper();
  const std::lock_guard<std::mutex> lock(k.mutex);
  k.budget = budget_bytes;
  k.drop_beyond_budget();
}

cv::Mat remembered_grey16(const fs::path& file) { return remembered(file, true); }

void remember_images(const std::string& name, std::vector<cv::Mat> images) {
  Keeper& k = keeper();
  const std::lock_guard<std::mutex> lock(k.mutex);
  if (k.budget > 0) k.keep({name, 0, 0, 0, kNamed}, std::move(images));
}

std::optional<std::vector<cv::Mat>> remembered_images(const std::string& name) {
  Keeper& k = keeper();
  const std::lock_guard<std::mutex> lock(k.mutex);
  return k.find({name, 0, 0, 0, kNamed});
}
cv::Mat remembered_color(const fs::path& file) { return remembered(file, false); }

}  // namespace olt
