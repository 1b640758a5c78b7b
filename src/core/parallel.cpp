#include "olt/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

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

}  // namespace olt
