#pragma once
// Independent iterations spread over the threads (OpenMP, one iteration at a time to whichever
// thread is free): the loop of every per-frame pass. An exception in one iteration stops nothing
// else; the first one caught is rethrown once all have ended, so a bad input still names its file.
#include <cstddef>
#include <functional>

namespace olt {

/// Runs body(0) ... body(n - 1) in parallel, in no particular order.
void parallel_for(size_t n, const std::function<void(size_t)>& body);

}  // namespace olt
