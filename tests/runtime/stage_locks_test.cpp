// The stage locks of one run: stages side by side whose keys name one lock file share it (locked once,
// neither waits for the other, one taking it while another waits for it shares what that one gets),
// stages with one key take turns, and a lock let go is locked afresh.
#include "runtime/stage_locks.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>

using namespace olt;

namespace {

// An acquire that counts the file locks taken, each a token that says when it is let go.
struct FileLocks {
  std::atomic<int> taken{0}, held{0};
  StageLocks::Acquire acquire() {
    return [this]() -> std::shared_ptr<void> {
      ++taken, ++held;
      return std::shared_ptr<void>(new int(0), [this](void* token) {
        delete static_cast<int*>(token);
        --held;
      });
    };
  }
};

// The value `future` gives; fails the test rather than hang where it never comes (a lock never let go).
template <class T>
T within_a_minute(std::future<T> future) {
  REQUIRE(future.wait_for(std::chrono::minutes(1)) == std::future_status::ready);
  return future.get();
}

}  // namespace

TEST_CASE("stage locks: two keys naming one lock file share it - locked once, again once both let go") {
  StageLocks locks;
  FileLocks file;
  StageLock first = locks.hold("stage-ab", "ab01", file.acquire());
  StageLock second = locks.hold("stage-ab", "ab02", file.acquire(), [] { FAIL("waited for its turn"); });
  CHECK(file.taken == 1);
  CHECK(file.held == 1);
  first = StageLock();
  CHECK(file.held == 1);  // the second still holds it
  second = StageLock();
  CHECK(file.held == 0);
  const StageLock third = locks.hold("stage-ab", "ab03", file.acquire());
  CHECK(file.taken == 2);
  CHECK(file.held == 1);
}

TEST_CASE("stage locks: other lock files are each locked") {
  StageLocks locks;
  FileLocks ab, cd;
  const StageLock first = locks.hold("stage-ab", "ab01", ab.acquire());
  const StageLock second = locks.hold("stage-cd", "cd01", cd.acquire());
  CHECK(ab.taken == 1);
  CHECK(cd.taken == 1);
}

TEST_CASE("stage locks: a stage taking a lock file while another waits for it shares what that one gets") {
  StageLocks locks;
  FileLocks file;
  std::promise<void> waiting, free;  // the first waits in acquire (another process holds the file) until `free`
  std::shared_future<void> freed = free.get_future().share();
  const StageLocks::Acquire slow = [&]() -> std::shared_ptr<void> {
    waiting.set_value();
    freed.wait();
    return file.acquire()();
  };
  std::promise<int> first_took, second_took;  // the file locks taken when each has its hold
  std::shared_future<int> second_has = second_took.get_future().share();
  std::thread first([&] {
    const StageLock held = locks.hold("stage-ab", "ab01", slow);
    first_took.set_value(file.taken);
    second_has.wait();  // held until the second has its hold
  });
  within_a_minute(waiting.get_future());
  std::thread second([&] {
    const StageLock held = locks.hold("stage-ab", "ab02", file.acquire(), [] { FAIL("waited for its turn"); });
    second_took.set_value(file.taken);
  });
  free.set_value();
  const int by_first = within_a_minute(first_took.get_future());
  REQUIRE(second_has.wait_for(std::chrono::minutes(1)) == std::future_status::ready);
  const int by_second = second_has.get();
  first.join();
  second.join();
  CHECK(by_first == 1);
  CHECK(by_second == 1);  // the first's lock, not one of its own
  CHECK(file.taken == 1);
  CHECK(file.held == 0);
}

TEST_CASE("stage locks: two stages of one key take turns - the second holds nothing until the first lets go") {
  StageLocks locks;
  FileLocks file;
  StageLock first = locks.hold("stage-ab", "ab01", file.acquire());
  std::promise<std::string> how;  // "waited" before it waits for its turn, else "took it at once"
  std::promise<int> held_then;    // the file locks held as the second has its turn
  std::thread other([&] {
    bool waited = false;
    const StageLock second = locks.hold("stage-ab", "ab01", file.acquire(), [&] {
      waited = true;
      how.set_value("waited");
    });
    if (!waited) how.set_value("took it at once");
    held_then.set_value(file.held);
  });
  const std::string said = within_a_minute(how.get_future());
  CHECK(said == "waited");
  if (said == "waited") first = StageLock();  // its turn over (else the other thread already has it)
  const int held = within_a_minute(held_then.get_future());
  other.join();
  CHECK(held == 1);        // its own: the first's was let go
  CHECK(file.taken == 2);  // locked afresh for the second
}

TEST_CASE("stage locks: a lock that cannot be had leaves the turn and the file free for the next stage") {
  StageLocks locks;
  FileLocks file;
  const StageLocks::Acquire stopped = []() -> std::shared_ptr<void> { throw std::runtime_error("stopped"); };
  CHECK_THROWS_WITH(locks.hold("stage-ab", "ab01", stopped), "stopped");
  const StageLock next = locks.hold("stage-ab", "ab01", file.acquire(), [] { FAIL("waited for its turn"); });
  CHECK(file.taken == 1);
}
