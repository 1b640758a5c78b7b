#include "olt/core/allocator.h"

#include <malloc.h>

namespace olt {

void keep_freed_memory() {
  mallopt(M_MMAP_THRESHOLD, 256 << 20);  // blocks below 256 MB come from the heap ...
  mallopt(M_TRIM_THRESHOLD, 512 << 20);  // ... which is returned to the system above 512 MB free
}

void return_freed_memory() { malloc_trim(0); }

}  // namespace olt
