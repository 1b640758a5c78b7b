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

/// At most this many blocks kept: the list of them has room for as many from keep_freed_pages on,
/// so that freeing a block allocates nothing (lists are freed in destructors).
constexpr std::size_t kMaxBlocks = 256;

FreedPages& freed() {
  static auto* pages = new FreedPages;  // NOLINT(cppcoreguidelines-owning-memory): see FreedPages
  return *pages;
}

std::size_t in_pages(std::size_t bytes) {
  static const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  return (bytes + page - 1) / page * page;
}

// Gives blocks back to the system, the oldest first, until the kept ones fit `limit`. Under the
// lock: a block freed makes room this way seldom (the limit is far above a cycle's lists).
void give_back_beyond(FreedPages& f, std::size_t limit) {
  std::size_t dropped = 0;
  for (; f.held > limit && dropped < f.blocks.size(); ++dropped) {
    munmap(f.blocks[dropped].second, f.blocks[dropped].first);
    f.held -= f.blocks[dropped].first;
  }
  f.blocks.erase(f.blocks.begin(), f.blocks.begin() + static_cast<std::ptrdiff_t>(dropped));
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
  {
    const std::lock_guard<std::mutex> lock(f.mutex);
    if (size <= f.limit && f.blocks.size() < f.blocks.capacity()) {  // room made: no allocation
      f.blocks.emplace_back(size, at);
      f.held += size;
      give_back_beyond(f, f.limit);  // the oldest make room (this one, the latest, stays)
      return;
    }
  }
  munmap(at, size);
}

void keep_freed_pages(std::size_t bytes) {
  FreedPages& f = freed();
  const std::lock_guard<std::mutex> lock(f.mutex);
  f.limit = bytes;
  f.blocks.reserve(kMaxBlocks);
  give_back_beyond(f, bytes);
}

std::size_t freed_pages_kept() {
  FreedPages& f = freed();
  const std::lock_guard<std::mutex> lock(f.mutex);
  return f.held;
}

}  // namespace olt
