#include "olt/core/fault.h"

#include <atomic>
#include <csignal>
#include <cstdlib>

namespace olt {
namespace {

// The count at which to die, read once: 0 where the environment names none.
long kill_after_frames() {
  static const long n = [] {
    const char* text = std::getenv("OLT_FAULT_KILL_AFTER_FRAMES");
    return text ? std::strtol(text, nullptr, 10) : 0L;
  }();
  return n;
}

std::atomic<long> frames_stored{0};

}  // namespace

void fault_point_frame_stored() {
  const long limit = kill_after_frames();
  if (limit > 0 && ++frames_stored >= limit) std::raise(SIGKILL);
}

}  // namespace olt
