#include "olt/core/fault.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <string>

namespace olt {
namespace {

// A plan read from the environment variable `name`, "WHAT:N"; {"", 0} (no plan) when unset or
// malformed (the variables are for tests only).
struct Plan {
  std::string what;
  long at = 0;
};

Plan plan_from(const char* name) {
  Plan p;
  const char* text = std::getenv(name);
  if (!text) return p;
  const std::string value = text;
  const auto colon = value.rfind(':');
  if (colon == std::string::npos) return p;
  p.what = value.substr(0, colon);
  p.at = std::strtol(value.c_str() + colon + 1, nullptr, 10);
  return p;
}

// OLT_FAULT_KILL_AT=WHERE:N, read once; WHERE a point's name or "*".
const Plan& kill_plan() {
  static const Plan plan = plan_from("OLT_FAULT_KILL_AT");
  return plan;
}

// OLT_FAULT_TERM_AT=WHERE:N, read once.
const Plan& term_plan() {
  static const Plan plan = plan_from("OLT_FAULT_TERM_AT");
  return plan;
}

// The passage's number where this passage of `where` is the plan's N-th, else 0 (each plan counts
// its own passages).
long due(const Plan& plan, std::atomic<long>& passages, std::string_view where) {
  if (plan.at <= 0 || (plan.what != "*" && plan.what != where)) return 0;
  const long n = ++passages;
  return n == plan.at ? n : 0;
}

std::atomic<long> kill_passages{0}, term_passages{0};

// OLT_FAULT_WRITE_ERROR=ENOSPC:N or EIO:N, read once.
const Plan& write_plan() {
  static const Plan plan = plan_from("OLT_FAULT_WRITE_ERROR");
  return plan;
}

// The plan's errno to fail with (0: none).
int write_error() {
  static const int error = [] {
    const std::string& name = write_plan().what;
    return name == "ENOSPC" ? ENOSPC : name == "EIO" ? EIO : 0;
  }();
  return error;
}

std::atomic<long> writes{0};

// OLT_FAULT_TERM_SIGNALS=K, read once: how many SIGTERMs the term plan sends (1 to 16; 1 unless set).
int term_signals() {
  static const int count = [] {
    const char* text = std::getenv("OLT_FAULT_TERM_SIGNALS");
    return text ? static_cast<int>(std::clamp(std::strtol(text, nullptr, 10), 1L, 16L)) : 1;
  }();
  return count;
}

}  // namespace

void fault_point(std::string_view where) {
  if (const long n = due(term_plan(), term_passages, where)) {
    const int signals = term_signals();
    const std::string line = "fault injection: " + (signals > 1 ? std::to_string(signals) + " SIGTERMs" : "SIGTERM") +
                             " at " + std::string(where) + " (passage " + std::to_string(n) + ")\n";
    [[maybe_unused]] const ssize_t written = ::write(2, line.data(), line.size());
    for (int i = 0; i < signals; ++i) std::raise(SIGTERM);  // each handled before raise returns
  }
  const long n = due(kill_plan(), kill_passages, where);
  if (n == 0) return;
  const std::string line =
      "fault injection: killed at " + std::string(where) + " (passage " + std::to_string(n) + ")\n";
  [[maybe_unused]] const ssize_t written = ::write(2, line.data(), line.size());
  std::raise(SIGKILL);
}

int injected_write_error() {
  const int error = write_error();
  if (error == 0 || write_plan().at <= 0) return 0;
  const long n = ++writes;
  if (n != write_plan().at) return 0;
  const std::string line = "fault injection: write " + std::to_string(n) + " fails with " + write_plan().what + "\n";
  [[maybe_unused]] const ssize_t written = ::write(2, line.data(), line.size());
  return error;
}

}  // namespace olt
