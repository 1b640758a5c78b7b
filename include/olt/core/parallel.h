#pragma once
// Independent iterations spread over the threads (oneTBB's work-stealing pool, which OpenCV shares;
// one iteration at a time to whichever thread is free): every parallel loop of olt. Threads that
// wait for work sleep rather than spin, so a busy machine loses nothing to them; how many threads
// there are is olt/core/threads.h's choice. An exception in one iteration stops nothing else; the
// first one caught is rethrown once all have ended, so a bad input still names its file.
#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

namespace olt {

/// Runs body(0) ... body(n - 1) in parallel, in no particular order.
void parallel_for(size_t n, const std::function<void(size_t)>& body);

/// The same for a loop of a few microseconds (a scan match's points, once per iteration): on the
/// calling thread alone while the machine's runnable threads, less this process's pool, fill every
/// CPU (detail::every_cpu_taken), since a worker woken then waits longer for a core than the whole
/// loop takes, and the caller waits for it; as parallel_for otherwise. The load is read at most
/// every 20 ms. /proc/loadavg and the CPU count are the whole machine's: inside a cpuset or a CPU
/// quota that others fill while the machine has idle CPUs, the loop stays parallel.
void parallel_for_brief(size_t n, const std::function<void(size_t)>& body);

/// Whether ok(i) holds for every i in 0 ... n - 1: asked in blocks of `block` in parallel (cheap
/// checks, such as a stat per file of 70,000), no more once one does not hold.
bool parallel_all(size_t n, const std::function<bool(size_t)>& ok, size_t block = 256);

/// Pieces of work that need none of each other (a job's stages that read none of each other's
/// results) run side by side: the first on the calling thread, the others where a thread is free
/// (on one thread, one after the other in order). Each is isolated: a thread waiting inside one for
/// its own parallel loops takes none of another's work, which could hold up the piece it waits in
/// or meet a lock that piece holds. Returns, for each, what it threw (null where it ended well);
/// returns once all have ended.
std::vector<std::exception_ptr> run_side_by_side(const std::vector<std::function<void()>>& work);

/// Work handed to the threads now and waited for later while the caller goes on with its own (a
/// laser map's loop matches, each started as soon as its keyframe exists, during the tracking).
/// wait() rethrows the first exception the work threw, and work not yet begun then does not run;
/// the destructor waits too (dropping what was thrown), and when an exception is leaving the
/// caller's scope it drops the work not yet begun.
class Background {
 public:
  Background();
  ~Background();
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;

  void run(std::function<void()> work);
  void wait();

 private:
  struct Group;
  std::unique_ptr<Group> group_;
  int uncaught_;  // exceptions under way when made: more at the destructor means one is leaving
};

namespace detail {
/// Whether other work takes every CPU, from /proc/loadavg's text ("0.52 0.58 0.59 9/123 4567": the
/// fourth field's first number counts the machine's runnable threads now): those, less the
/// `own_threads` this process may run, at least `cpus`. False where the text is not such.
bool every_cpu_taken(std::string_view loadavg, size_t cpus, size_t own_threads);
/// parallel_for_brief with its choice made: on the calling thread, or over the threads.
void parallel_for_brief(size_t n, const std::function<void(size_t)>& body, bool on_caller);
}  // namespace detail

}  // namespace olt
