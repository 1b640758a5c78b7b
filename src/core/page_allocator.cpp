#include "olt/core/page_allocator.h"

#include <sys/mman.h>

#include <cstdint>

namespace olt {

void* map_pages(std::size_t bytes) {
  void* at = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (at == MAP_FAILED) throw std::bad_alloc();
  advise_huge_pages(at, bytes);  // a list of 10,000 frames' files is filled at once as well
  return at;
}

void unmap_pages(void* at, std::size_t bytes) { munmap(at, bytes); }

void advise_huge_pages(void* at, std::size_t bytes) {
  constexpr std::uintptr_t kHuge = 2 << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(at);
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1), last = (begin + bytes) & ~(kHuge - 1);
  // Advice only: where the kernel declines it (THP off), the pages are the small ones as before.
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

}  // namespace olt
