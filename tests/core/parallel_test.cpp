// The parallel loops and background work: every iteration once, failures told after all have run;
// when a loop of microseconds stays on the calling thread (every CPU taken by other work, read from
// /proc/loadavg's text, given here).
#include "olt/core/parallel.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace olt;

TEST_CASE("parallel: every CPU taken when the runnable threads, less this process's, fill them") {
  // 2 CPUs, a pool of 2: taken from 4 runnable threads on (two of them may be ours).
  CHECK(detail::every_cpu_taken("6.10 3.02 1.20 8/140 30211\n", 2, 2));
  CHECK(detail::every_cpu_taken("6.10 3.02 1.20 4/140 30211\n", 2, 2));
  CHECK_FALSE(detail::every_cpu_taken("6.10 3.02 1.20 3/140 30211\n", 2, 2));
  CHECK_FALSE(detail::every_cpu_taken("0.08 0.10 0.09 1/98 30211\n", 2, 2));
  // 64 CPUs: 40 runnable threads leave cores free.
  CHECK_FALSE(detail::every_cpu_taken("40.0 40.0 40.0 40/900 1\n", 64, 4));
  CHECK(detail::every_cpu_taken("70.0 70.0 70.0 70/900 1\n", 64, 4));
}

TEST_CASE("parallel: a /proc/loadavg that is not the kernel's form leaves the loops parallel") {
  for (const char* text : {"", "0.1 0.2 0.3", "0.1 0.2 0.3 ", "0.1 0.2 0.3 x/9 1", "0.1 0.2 0.3 9", "0.1 0.2 0.3 /9 1"})
    CHECK_FALSE(detail::every_cpu_taken(text, 2, 2));
  CHECK_FALSE(detail::every_cpu_taken("9.0 9.0 9.0 9/100 1\n", 0, 2));  // no CPU count
}

TEST_CASE("parallel: a brief loop runs every iteration once and rethrows the first failure after all ran") {
  for (const bool on_caller : {true, false}) {
    INFO("on the calling thread: " << on_caller);
    std::vector<std::atomic<int>> runs(300);
    detail::parallel_for_brief(
        runs.size(), [&](size_t i) { ++runs[i]; }, on_caller);
    for (const auto& r : runs) CHECK(r == 1);

    std::atomic<int> ran{0};
    CHECK_THROWS_WITH(detail::parallel_for_brief(
                          50,
                          [&](size_t i) {
                            ++ran;
                            if (i == 7) throw std::runtime_error("iteration 7");
                          },
                          on_caller),
                      "iteration 7");
    CHECK(ran == 50);
  }
}

TEST_CASE("parallel: a brief loop left to the calling thread runs there, in order") {
  const auto caller = std::this_thread::get_id();
  std::vector<size_t> order;
  bool elsewhere = false;
  detail::parallel_for_brief(
      100,
      [&](size_t i) {
        order.push_back(i);
        elsewhere = elsewhere || std::this_thread::get_id() != caller;
      },
      true);
  CHECK_FALSE(elsewhere);
  REQUIRE(order.size() == 100);
  for (size_t i = 0; i < order.size(); ++i) CHECK(order[i] == i);
}

TEST_CASE("parallel: background work is done by wait, and by the destructor") {
  std::vector<std::atomic<int>> done(40);
  {
    Background work;
    for (size_t i = 0; i < done.size(); ++i) work.run([&, i] { ++done[i]; });
    work.wait();
    for (const auto& d : done) CHECK(d == 1);
    for (size_t i = 0; i < done.size(); ++i) work.run([&, i] { ++done[i]; });
  }  // the destructor waits for the second round
  for (const auto& d : done) CHECK(d == 2);
}

TEST_CASE("parallel: the caller goes on while background work waits for it") {
  // The work cannot end before the caller, after run() returned, says so: run() did not wait for it
  // (with no other thread, the work runs in wait(), after the caller spoke).
  std::promise<void> caller_went_on;
  std::shared_future<void> told = caller_went_on.get_future().share();
  bool work_saw_it = false;
  Background work;
  work.run([&] {
    told.wait();
    work_saw_it = true;
  });
  caller_went_on.set_value();
  work.wait();
  CHECK(work_saw_it);
}

TEST_CASE("parallel: background work's failure is rethrown by wait") {
  Background work;
  work.run([] { throw std::runtime_error("loop match failed"); });
  CHECK_THROWS_WITH(work.wait(), "loop match failed");
}
