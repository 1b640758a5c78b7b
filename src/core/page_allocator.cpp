#include "olt/core/page_allocator.h"

#include <sys/mman.h>

#include "olt/core/huge_pages.h"

namespace olt {

void* map_pages(std::size_t bytes) {
  void* at = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (at == MAP_FAILED) throw std::bad_alloc();
  advise_huge_pages(at, bytes);  // a list of 10,000 frames' files is filled at once as well
  return at;
}

void unmap_pages(void* at, std::size_t bytes) { munmap(at, bytes); }

}  // namespace olt
