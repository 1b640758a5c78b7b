#pragma once
// Deterministic fault injection, for the tests of "killed anywhere, nothing lost": a test names the
// moment in the environment instead of guessing it with a timer, so a busy machine moves nothing.
//   OLT_FAULT_KILL_AFTER_FRAMES=N   the process kills itself (SIGKILL) once N frames are stored
// Unset (every user's case), a fault point costs one relaxed atomic read.
namespace olt {

/// A frame's files are in the cache: counts, and kills the process at the count the environment names.
void fault_point_frame_stored();

}  // namespace olt
