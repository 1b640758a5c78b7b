#pragma once
// Two pieces of work that can only both end well if they run at once: each says it has begun and
// waits for the other. The wait is bounded so that a fault fails a test rather than hangs it; it is
// not a timing.
#include <chrono>
#include <future>

namespace olt::test {

class Rendezvous {
 public:
  /// Called by piece 0 and by piece 1, once each: whether the other began too.
  bool meet(int side) {
    began_[side].set_value();
    return other_[1 - side].wait_for(std::chrono::minutes(2)) == std::future_status::ready;
  }

 private:
  std::promise<void> began_[2];
  std::shared_future<void> other_[2] = {began_[0].get_future().share(), began_[1].get_future().share()};
};

}  // namespace olt::test
