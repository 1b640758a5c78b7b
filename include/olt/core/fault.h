#pragma once
// Deterministic fault injection, for the tests of "killed anywhere, nothing lost": a test names the
// moment in the environment instead of guessing it with a timer, so a busy machine moves nothing.
//   OLT_FAULT_KILL_AT=WHERE:N      the process kills itself (SIGKILL) at the N-th passage of the
//                                  fault point WHERE (`*`: of any point), after saying so on stderr
//   OLT_FAULT_TERM_AT=WHERE:N      the process sends itself SIGTERM there instead (what Slurm at a
//                                  time limit, Kubernetes or Ctrl-C does), and goes on
//   OLT_FAULT_TERM_SIGNALS=K       ... K SIGTERMs there (1 to 16), one right after the other (2: a
//                                  second signal while the run stops, which ends it at once)
//   OLT_FAULT_WRITE_ERROR=ERROR:N  the N-th write of a file by this process (cache entries, outputs,
//                                  logs, records: every write, append and copy) fails with ERROR,
//                                  ENOSPC or EIO, as a full or failing disk would
// The points, in the order a run passes them: `artifact_written` (a cache entry's files written,
// not yet in place), `artifact_stored` (in place), `log_appended` (a line added to the cache's log),
// `unit_stored` (a unit of a stage, e.g. a labeled frame, in place), `published_file` (one output
// file staged inside the output), `manifest_next` (the changes staged with the manifest, not yet
// published), `publish_committed` (the staged changes are the output's pending publish, none made
// yet), `file_moved` (one staged file moved into place). Unset
// (every user's case), a fault point costs two comparisons and a write one.
#include <string_view>

namespace olt {

/// A moment where a kill must lose nothing: counts, and kills where the environment says.
void fault_point(std::string_view where);

/// Called before each write of a file: the error number it must fail with (OLT_FAULT_WRITE_ERROR),
/// 0 (every user's case) to go on.
int injected_write_error();

}  // namespace olt
