// The stage locks of one run: stages side by side whose keys name one lock file share it (locked once,
// neither waits for the other), stages with one key take turns, and a lock let go is locked afresh.
#include "runtime/stage_locks.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <future>
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

}  // namespace

TEST_CASE("stage locks: two keys naming one lock file share it - locked once, again once both let go") {
  StageLocks locks;
  FileLocks file;
  auto first = locks.hold("stage-ab", "ab01", file.acquire());
  auto second = locks.hold("stage-ab", "ab02", file.acquire(), [] { FAIL("waited for its turn"); });
  CHECK(file.taken == 1);
  CHECK(file.held == 1);
  first.reset();
  CHECK(file.held == 1);  // the second still holds it
  second.reset();
  CHECK(file.held == 0);
  auto third = locks.hold("stage-ab", "ab03", file.acquire());
  CHECK(file.taken == 2);
  CHECK(file.held == 1);
}

TEST_CASE("stage locks: other lock files are each locked") {
  StageLocks locks;
  FileLocks ab, cd;
  auto first = locks.hold("stage-ab", "ab01", ab.acquire());
  auto second = locks.hold("stage-cd", "cd01", cd.acquire());
  CHECK(ab.taken == 1);
  CHECK(cd.taken == 1);
}

TEST_CASE("stage locks: two stages of one key take turns - the second holds nothing until the first lets go") {
  StageLocks locks;
  FileLocks file;
  auto first = locks.hold("stage-ab", "ab01", file.acquire());
  std::promise<std::string> how;  // "waited" before it waits for its turn, else "took it at once"
  std::promise<int> held_then;    // the file locks held as the second has its turn
  std::thread other([&] {
    bool waited = false;
    auto second = locks.hold("stage-ab", "ab01", file.acquire(), [&] {
      waited = true;
      how.set_value("waited");
    });
    if (!waited) how.set_value("took it at once");
    held_then.set_value(file.held);
  });
  const std::string said = how.get_future().get();
  CHECK(said == "waited");
  if (said == "waited") first.reset();  // its turn over (else the other thread already has it)
  const int held = held_then.get_future().get();
  other.join();
  CHECK(held == 1);        // its own: the first's was let go
  CHECK(file.taken == 2);  // locked afresh for the second
}

TEST_CASE("stage locks: a lock that cannot be had leaves the turn and the file free for the next stage") {
  StageLocks locks;
  FileLocks file;
  const StageLocks::Acquire stopped = []() -> std::shared_ptr<void> { throw std::runtime_error("stopped"); };
  CHECK_THROWS_WITH(locks.hold("stage-ab", "ab01", stopped), "stopped");
  auto next = locks.hold("stage-ab", "ab01", file.acquire(), [] { FAIL("waited for its turn"); });
  CHECK(file.taken == 1);
}
