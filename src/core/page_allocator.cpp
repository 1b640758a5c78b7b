#include "olt/core/page_allocator.h"

#include <sys/mman.h>

namespace olt {

void* map_pages(std::size_t bytes) {
  void* at = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (at == MAP_FAILED) throw std::bad_alloc();
  return at;
}

void unmap_pages(void* at, std::size_t bytes) { munmap(at, bytes); }

}  // namespace olt
