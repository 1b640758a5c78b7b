#include "olt/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>

namespace olt {

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

bool parallel_all(size_t n, const std::function<bool(size_t)>& ok, size_t block) {
  std::atomic<bool> all{true};
  parallel_for((n + block - 1) / block, [&](size_t b) {
    for (size_t i = b * block; i < std::min(n, (b + 1) * block) && all; ++i)
      if (!ok(i)) all = false;
  });
  return all;
}

}  // namespace olt
