#pragma once
// Independent iterations spread over the threads (oneTBB's work-stealing pool, which OpenCV shares;
// one iteration at a time to whichever thread is free): every parallel loop of olt. Threads that
// wait for work sleep rather than spin, so a busy machine loses nothing to them; how many threads
// there are is olt/core/threads.h's choice. An exception in one iteration stops nothing else; the
// first one caught is rethrown once all have ended, so a bad input still names its file.
#include <cstddef>
#include <functional>

namespace olt {

/// Runs body(0) ... body(n - 1) in parallel, in no particular order.
void parallel_for(size_t n, const std::function<void(size_t)>& body);

}  // namespace olt
