// The parallel loops and background work: every iteration once, failures told after all have run;
// when a loop of microseconds stays on the calling thread (every CPU taken by other work, read from
// /proc/loadavg's text, given here).
#include "olt/core/parallel.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

#include "support/rendezvous.h"

using namespace olt;
using olt::test::Rendezvous;

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

TEST_CASE("parallel: work side by side runs each piece once and says what each threw") {
  std::vector<std::atomic<int>> ran(5);
  std::vector<std::function<void()>> work;
  for (size_t i = 0; i < ran.size(); ++i)
    work.emplace_back([&, i] {
      ++ran[i];
      if (i == 1 || i == 3) throw std::runtime_error("piece " + std::to_string(i));
    });
  const std::vector<std::exception_ptr> failures = run_side_by_side(work);
  for (const auto& r : ran) CHECK(r == 1);
  REQUIRE(failures.size() == 5);
  for (size_t i : {0, 2, 4}) CHECK_FALSE(failures[i]);
  for (size_t i : {1, 3}) CHECK_THROWS_WITH(std::rethrow_exception(failures[i]), "piece " + std::to_string(i));
}

TEST_CASE("parallel: work side by side on one thread runs in order") {
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  std::vector<size_t> order;
  std::vector<std::function<void()>> work;
  for (size_t i = 0; i < 4; ++i) work.emplace_back([&, i] { order.push_back(i); });
  run_side_by_side(work);
  CHECK(order == std::vector<size_t>{0, 1, 2, 3});
}

TEST_CASE("parallel: pieces side by side each have a thread where the process has two") {
  if (tbb::this_task_arena::max_concurrency() < 2) {
    WARN("one thread in this process: the pieces run one after the other, nothing to check");
    return;
  }
  // Each piece waits for the other to begin: both meet only if they run at once.
  Rendezvous rendezvous;
  std::atomic<bool> met0{false}, met1{false};
  run_side_by_side({[&] { met0 = rendezvous.meet(0); }, [&] { met1 = rendezvous.meet(1); }});
  const bool met = met0 && met1;
  CHECK(met);
}
