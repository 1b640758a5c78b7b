#include "olt/core/allocator.h"

#include <malloc.h>
#include <sys/mman.h>

namespace olt {

void keep_freed_memory() {
  mallopt(M_MMAP_THRESHOLD, 256 << 20);  // blocks below 256 MB come from the heap ...
  mallopt(M_TRIM_THRESHOLD, 512 << 20);  // ... which is returned to the system above 512 MB free
}

void return_freed_memory() { malloc_trim(0); }

void* map_pages(std::size_t bytes) {
  void* at = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (at == MAP_FAILED) throw std::bad_alloc();
  return at;
}

void unmap_pages(void* at, std::size_t bytes) { munmap(at, bytes); }

}  // namespace olt
