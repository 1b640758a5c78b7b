// made_once: a value made on first use, once, whichever threads ask; made again after a throw.
#include "olt/core/made_once.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

TEST_CASE("made_once makes its value once for eight threads asking at the same time") {
  std::atomic<int> made{0}, asking{0};
  const auto value = olt::made_once<int>([&] {
    ++made;
    // Made only once all eight have asked: without the wait for the first, each would make it.
    for (int i = 0; i < 100000 && asking < 8; ++i) std::this_thread::sleep_for(std::chrono::microseconds(100));
    return std::make_shared<const int>(42);
  });
  std::vector<std::shared_ptr<const int>> got(8);
  std::vector<std::thread> threads;
  for (size_t i = 0; i < got.size(); ++i)
    threads.emplace_back([&, i] {
      ++asking;
      got[i] = value();
    });
  for (auto& t : threads) t.join();
  CHECK(asking == 8);
  CHECK(made == 1);
  for (const auto& g : got) {
    REQUIRE(g);
    CHECK(g.get() == got[0].get());  // the same value, not equal copies
    CHECK(*g == 42);
  }
}

TEST_CASE("made_once throws what its maker threw, and the next call makes the value again") {
  int calls = 0;
  const auto value = olt::made_once<int>([&] {
    if (++calls == 1) throw std::runtime_error("scene_points.bin: cut short");
    return std::make_shared<const int>(7);
  });
  CHECK_THROWS_WITH(value(), "scene_points.bin: cut short");
  CHECK(*value() == 7);
  CHECK(*value() == 7);
  CHECK(calls == 2);
}
