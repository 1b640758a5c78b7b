#include "olt/core/decoded_images.h"

#include <sys/stat.h>

#include <list>
#include <map>
#include <mutex>
#include <string>
#include <tuple>

#include "olt/core/image.h"

namespace olt {
namespace {

// An image file as the keeper knows it: path, size, modification time (ns), inode, and how it was
// decoded (grey16 or colour).
using Key = std::tuple<std::string, int64_t, int64_t, uint64_t, bool>;

struct Keeper {
  std::mutex mutex;
  size_t budget = 0, bytes = 0;
  std::list<std::pair<Key, cv::Mat>> images;  // most recently read first
  std::map<Key, std::list<std::pair<Key, cv::Mat>>::iterator> by_key;

  void drop_beyond_budget() {
    while (bytes > budget && !images.empty()) {
      bytes -= images.back().second.total() * images.back().second.elemSize();
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
            st.st_ino, grey16};
    return true;
  };
  Key key;
  if (!key_now(&key)) return decode();  // its error names the file
  {
    const std::lock_guard<std::mutex> lock(k.mutex);
    if (const auto it = k.by_key.find(key); it != k.by_key.end()) {
      k.images.splice(k.images.begin(), k.images, it->second);
      return it->second->second;
    }
  }
  cv::Mat image = decode();  // outside the lock: other threads decode other frames meanwhile
  Key after;
  if (!key_now(&after) || after != key) return image;  // replaced while it was read: not kept
  const std::lock_guard<std::mutex> lock(k.mutex);
  if (k.by_key.count(key)) return image;  // another thread decoded it meanwhile
  k.images.emplace_front(key, image);
  k.by_key[key] = k.images.begin();
  k.bytes += image.total() * image.elemSize();
  k.drop_beyond_budget();
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
cv::Mat remembered_color(const fs::path& file) { return remembered(file, false); }

}  // namespace olt
