#pragma once
// A scope in which the process keeps memory, as `olt watch` does (olt/core/process_memory.h); it
// keeps nothing again when the scope ends, a failed check or an exception included.
#include <cstddef>

#include "olt/core/process_memory.h"

namespace olt::test {

struct KeepingMemory {
  explicit KeepingMemory(size_t budget_bytes = size_t{64} << 20) { keep_in_memory(budget_bytes); }
  ~KeepingMemory() { keep_in_memory(0); }
  KeepingMemory(const KeepingMemory&) = delete;
  KeepingMemory& operator=(const KeepingMemory&) = delete;
};

}  // namespace olt::test
