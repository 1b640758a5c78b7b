#include "olt/core/huge_pages.h"

#include <sys/mman.h>

#include <cstdint>
#include <fstream>

namespace olt {

std::size_t huge_page_bytes() {
  static const std::size_t bytes = [] {
    std::size_t said = 0;
    std::ifstream("/sys/kernel/mm/transparent_hugepage/hpage_pmd_size") >> said;
    // A power of two, as the kernel's is; else the x86-64 size.
    return said >= 4096 && (said & (said - 1)) == 0 ? said : std::size_t{2} << 20;
  }();
  return bytes;
}

void advise_huge_pages(void* at, std::size_t bytes) {
  const std::uintptr_t huge = huge_page_bytes(), begin = reinterpret_cast<std::uintptr_t>(at);
  const std::uintptr_t first = (begin + huge - 1) & ~(huge - 1), last = (begin + bytes) & ~(huge - 1);
  // Advice only: where the kernel declines it, the pages are the small ones as before.
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

}  // namespace olt
