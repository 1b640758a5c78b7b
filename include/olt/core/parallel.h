#pragma once
// Independent iterations spread over the threads (OpenMP, one iteration at a time to whichever
// thread is free): the loop of every per-frame pass. An exception in one iteration stops nothing
// else; the first one caught is rethrown once all have ended, so a bad input still names its file.
#include <cstddef>
#include <functional>

namespace olt {

/// Runs body(0) ... body(n - 1) in parallel, in no particular order.
void parallel_for(size_t n, const std::function<void(size_t)>& body);

/// Call first in main: OpenMP threads that wait for work sleep instead of spinning
/// (OMP_WAIT_POLICY=passive) unless the user chose a policy. Spinning wins a few percent on an idle
/// machine and loses half the speed on a shared one (two runs of the synthetic robot at once on 2
/// cores: 47.7 s spinning, 24.8 s sleeping). libgomp reads the variable when it loads, before main:
/// the process sets it and executes itself again, once (about 20 ms).
void wait_passively(char** argv);

}  // namespace olt
