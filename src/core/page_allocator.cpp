#include "olt/core/page_allocator.h"

#include <sys/mman.h>
#include <unistd.h>

#include <mutex>
#include <utility>
#include <vector>

#include "olt/core/huge_pages.h"

namespace olt {
namespace {

// Blocks freed and kept mapped for the next block of the same size: a list repeats its sizes from
// cycle to cycle (a vector grown by doubling, then trimmed to what it holds), so a block is found
// by its size in pages, not split or joined. Made once and never destroyed: a list freed while the
// process exits may still come back to it.
struct FreedPages {
  std::mutex mutex;
  std::vector<std::pair<std::size_t, void*>> blocks;  ///< (bytes, rounded to pages; where)
  std::size_t held = 0, limit = 0;
};

FreedPages& freed() {
  static auto* pages = new FreedPages;  // NOLINT(cppcoreguidelines-owning-memory): see FreedPages
  return *pages;
}

std::size_t in_pages(std::size_t bytes) {
  static const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  return (bytes + page - 1) / page * page;
}

// Takes blocks out of those kept, the oldest first, until the kept ones fit `limit`: to be given
// back to the system once the lock is let go (64 MB of pages take a while).
std::vector<std::pair<std::size_t, void*>> beyond(FreedPages& f, std::size_t limit) {
  std::size_t dropped = 0;
  while (f.held > limit && dropped < f.blocks.size()) f.held -= f.blocks[dropped++].first;
  std::vector<std::pair<std::size_t, void*>> out(f.blocks.begin(),
                                                 f.blocks.begin() + static_cast<std::ptrdiff_t>(dropped));
  f.blocks.erase(f.blocks.begin(), f.blocks.begin() + static_cast<std::ptrdiff_t>(dropped));
  return out;
}

void unmap_all(const std::vector<std::pair<std::size_t, void*>>& blocks) {
  for (const auto& [size, at] : blocks) munmap(at, size);
}

}  // namespace

void* map_pages(std::size_t bytes) {
  const std::size_t size = in_pages(bytes);
  FreedPages& f = freed();
  {
    const std::lock_guard<std::mutex> lock(f.mutex);
    // The latest freed first: its pages are the likeliest in the processor's caches.
    for (size_t i = f.blocks.size(); i-- > 0;)
      if (f.blocks[i].first == size) {
        void* at = f.blocks[i].second;
        f.blocks.erase(f.blocks.begin() + static_cast<std::ptrdiff_t>(i));
        f.held -= size;
        return at;
      }
  }
  void* at = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (at == MAP_FAILED) throw std::bad_alloc();
  advise_huge_pages(at, size);  // a list of 10,000 frames' files is filled at once too
  return at;
}

void unmap_pages(void* at, std::size_t bytes) {
  const std::size_t size = in_pages(bytes);
  FreedPages& f = freed();
  bool kept = false;
  std::vector<std::pair<std::size_t, void*>> dropped;
  {
    const std::lock_guard<std::mutex> lock(f.mutex);
    kept = size <= f.limit;
    if (kept) {
      f.blocks.emplace_back(size, at);
      f.held += size;
      dropped = beyond(f, f.limit);  // the oldest make room (this one, the latest, stays)
    }
  }
  if (!kept) munmap(at, size);
  unmap_all(dropped);
}

void keep_freed_pages(std::size_t bytes) {
  FreedPages& f = freed();
  std::vector<std::pair<std::size_t, void*>> dropped;
  {
    const std::lock_guard<std::mutex> lock(f.mutex);
    f.limit = bytes;
    dropped = beyond(f, bytes);
  }
  unmap_all(dropped);
}

std::size_t freed_pages_kept() {
  FreedPages& f = freed();
  const std::lock_guard<std::mutex> lock(f.mutex);
  return f.held;
}

}  // namespace olt
