#pragma once
// A value made on first use, from any thread, and shared after.
#include <functional>
#include <memory>
#include <mutex>
#include <utility>

namespace olt {

/// A function that returns what `make` returns, made on its first call (on whichever thread calls
/// first; the others wait for it) and the same after. Where `make` throws, the call throws and the
/// next call makes it again. `make` must not call the function it is given to (it would wait for
/// itself), nor hand work that does to other threads while it waits.
template <typename T>
std::function<std::shared_ptr<const T>()> made_once(std::function<std::shared_ptr<const T>()> make) {
  struct Once {
    std::mutex mutex;
    std::shared_ptr<const T> value;
  };
  auto once = std::make_shared<Once>();
  return [once, make = std::move(make)] {
    const std::lock_guard<std::mutex> lock(once->mutex);
    if (!once->value) once->value = make();
    return once->value;
  };
}

}  // namespace olt
