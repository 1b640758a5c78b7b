#include "olt/core/fault.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <string>

namespace olt {
namespace {

struct KillPlan {
  std::string where;  ///< a point's name, or "*"
  long at = 0;        ///< the passage to die at; 0: never
};

// OLT_FAULT_KILL_AT=WHERE:N, read once; anything else is no plan (the variable is for tests only).
const KillPlan& kill_plan() {
  static const KillPlan plan = [] {
    KillPlan p;
    const char* text = std::getenv("OLT_FAULT_KILL_AT");
    if (!text) return p;
    const std::string value = text;
    const auto colon = value.rfind(':');
    if (colon == std::string::npos) return p;
    p.where = value.substr(0, colon);
    p.at = std::strtol(value.c_str() + colon + 1, nullptr, 10);
    return p;
  }();
  return plan;
}

std::atomic<long> passages{0};

struct WritePlan {
  int error = 0;  ///< errno to fail with; 0: never
  long at = 0;    ///< the write to fail
};

// OLT_FAULT_WRITE_ERROR=ENOSPC:N or EIO:N, read once; anything else is no plan.
const WritePlan& write_plan() {
  static const WritePlan plan = [] {
    WritePlan p;
    const char* text = std::getenv("OLT_FAULT_WRITE_ERROR");
    if (!text) return p;
    const std::string value = text;
    const auto colon = value.rfind(':');
    if (colon == std::string::npos) return p;
    const std::string name = value.substr(0, colon);
    p.error = name == "ENOSPC" ? ENOSPC : name == "EIO" ? EIO : 0;
    p.at = std::strtol(value.c_str() + colon + 1, nullptr, 10);
    return p;
  }();
  return plan;
}

std::atomic<long> writes{0};

}  // namespace

void fault_point(std::string_view where) {
  const KillPlan& plan = kill_plan();
  if (plan.at <= 0 || (plan.where != "*" && plan.where != where)) return;
  const long n = ++passages;
  if (n != plan.at) return;
  const std::string line =
      "fault injection: killed at " + std::string(where) + " (passage " + std::to_string(n) + ")\n";
  [[maybe_unused]] const ssize_t written = ::write(2, line.data(), line.size());
  std::raise(SIGKILL);
}

int injected_write_error() {
  const WritePlan& plan = write_plan();
  if (plan.error == 0 || plan.at <= 0) return 0;
  const long n = ++writes;
  if (n != plan.at) return 0;
  const std::string line =
      "fault injection: write " + std::to_string(n) + " fails with " + (plan.error == ENOSPC ? "ENOSPC" : "EIO") + "\n";
  [[maybe_unused]] const ssize_t written = ::write(2, line.data(), line.size());
  return plan.error;
}

}  // namespace olt
