#pragma once
// Deterministic fault injection, for the tests of "killed anywhere, nothing lost": a test names the
// moment in the environment instead of guessing it with a timer, so a busy machine moves nothing.
//   OLT_FAULT_KILL_AT=WHERE:N   the process kills itself (SIGKILL) at the N-th passage of the fault
//                               point WHERE (`*`: of any point), after saying so on stderr
// The points, in the order a run passes them: `artifact_written` (a cache entry's files written,
// not yet in place), `artifact_stored` (in place), `unit_stored` (a unit of a stage, e.g. a labeled frame, in place),
// `published_file` (one output file staged beside the output), `manifest_next` (the new output
// staged with its manifest, not yet switched in). Unset (every user's case), a fault point costs one comparison.
#include <string_view>

namespace olt {

/// A moment where a kill must lose nothing: counts, and kills where the environment says.
void fault_point(std::string_view where);

}  // namespace olt
