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

/// Whether ok(i) holds for every i in 0 ... n - 1: asked in blocks of `block` in parallel (cheap
/// checks, such as a stat per file of 70,000), no more once one does not hold.
bool parallel_all(size_t n, const std::function<bool(size_t)>& ok, size_t block = 256);

}  // namespace olt
