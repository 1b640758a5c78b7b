#include "olt/core/parallel.h"

#include <fcntl.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <exception>
#include <limits>
#include <mutex>

namespace olt {

namespace detail {

bool every_cpu_taken(std::string_view loadavg, size_t cpus, size_t own_threads) {
  for (int field = 0; field < 3; ++field) {  // past the three load averages
    const size_t end = loadavg.find(' ');
    if (end == std::string_view::npos) return false;
    loadavg.remove_prefix(end + 1);
  }
  size_t runnable = 0;
  const auto [end, error] = std::from_chars(loadavg.data(), loadavg.data() + loadavg.size(), runnable);
  if (error != std::errc() || end == loadavg.data() || end == loadavg.data() + loadavg.size() || *end != '/')
    return false;
  return cpus > 0 && runnable >= cpus + own_threads;
}

}  // namespace detail

namespace {

bool read_every_cpu_taken() {
  const int fd = ::open("/proc/loadavg", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  char text[128];
  const ssize_t got = ::read(fd, text, sizeof(text));
  ::close(fd);
  const long cpus = ::sysconf(_SC_NPROCESSORS_ONLN);
  if (got <= 0 || cpus <= 0) return false;
  // The pool: the arena's threads, under the cap configure_threads() set (OLT_THREADS, the quota).
  const size_t pool = std::min(static_cast<size_t>(tbb::this_task_arena::max_concurrency()),
                               tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  return detail::every_cpu_taken(std::string_view(text, static_cast<size_t>(got)), static_cast<size_t>(cpus), pool);
}

// read_every_cpu_taken(), read again once 20 ms have passed (a read costs microseconds; a loop
// asking may run thousands of times a second).
bool every_cpu_taken_now() {
  static std::atomic<int64_t> read_at{std::numeric_limits<int64_t>::min() / 2};
  static std::atomic<bool> taken{false};
  const int64_t now =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count();
  if (now - read_at.load(std::memory_order_relaxed) >= 20'000) {
    read_at.store(now, std::memory_order_relaxed);
    taken.store(read_every_cpu_taken(), std::memory_order_relaxed);
  }
  return taken.load(std::memory_order_relaxed);
}

}  // namespace

void parallel_for(size_t n, const std::function<void(size_t)>& body) {
  std::exception_ptr failure;
  std::mutex mutex;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, 1),
      [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          try {
            body(i);
          } catch (...) {
            std::lock_guard<std::mutex> lock(mutex);
            if (!failure) failure = std::current_exception();
          }
        }
      },
      tbb::simple_partitioner());
  if (failure) std::rethrow_exception(failure);
}

namespace detail {

void parallel_for_brief(size_t n, const std::function<void(size_t)>& body, bool on_caller) {
  if (!on_caller && n > 1) {
    // Isolated: while it waits for its blocks, the caller takes none of the longer work it handed
    // to the threads before (a laser map's loop matches), which would hold up its own loop.
    tbb::this_task_arena::isolate([&] { parallel_for(n, body); });
    return;
  }
  std::exception_ptr failure;  // as parallel_for: every iteration runs, the first failure rethrown
  for (size_t i = 0; i < n; ++i) {
    try {
      body(i);
    } catch (...) {
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace detail

void parallel_for_brief(size_t n, const std::function<void(size_t)>& body) {
  detail::parallel_for_brief(n, body, n > 1 && every_cpu_taken_now());
}

bool parallel_all(size_t n, const std::function<bool(size_t)>& ok, size_t block) {
  std::atomic<bool> all{true};
  parallel_for((n + block - 1) / block, [&](size_t b) {
    for (size_t i = b * block; i < std::min(n, (b + 1) * block) && all; ++i)
      if (!ok(i)) all = false;
  });
  return all;
}

std::vector<std::exception_ptr> run_side_by_side(const std::vector<std::function<void()>>& work) {
  std::vector<std::exception_ptr> failures(work.size());
  const auto run = [&](size_t i) {
    tbb::this_task_arena::isolate([&] {
      try {
        work[i]();
      } catch (...) {
        failures[i] = std::current_exception();
      }
    });
  };
  tbb::task_group others;
  // Handed out last first: the thread that waits takes back the last handed out first, so what no
  // other thread took runs here in order; another thread takes the first handed out.
  for (size_t i = work.size(); i-- > 1;) others.run([&run, i] { run(i); });
  if (!work.empty()) run(0);
  others.wait();
  return failures;
}

struct Background::Group {
  tbb::task_group tasks;
};

Background::Background() : group_(std::make_unique<Group>()), uncaught_(std::uncaught_exceptions()) {}

Background::~Background() {
  // Left by an exception: the work not yet begun is dropped, not waited for.
  if (std::uncaught_exceptions() > uncaught_) group_->tasks.cancel();
  try {
    wait();
  } catch (...) {  // a destructor has no one to tell; wait() is where callers hear of failures
  }
}

void Background::run(std::function<void()> work) { group_->tasks.run(std::move(work)); }

void Background::wait() { group_->tasks.wait(); }

}  // namespace olt
