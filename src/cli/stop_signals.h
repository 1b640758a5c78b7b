#pragma once
// SIGINT (Ctrl-C) and SIGTERM (Slurm at a time limit, Kubernetes stopping a pod, systemd) asking a
// command that computes to stop at its next boundary (RunOptions::stop) rather than die mid-way:
// what it finished is kept and synced, nothing is half-published. A second signal (of either) ends
// the process at once. Private to cli/.
#include <atomic>

namespace olt {

/// Installs the handlers; the flag they set.
const std::atomic<bool>& stop_on_signals();

/// The signal that set the flag (0: none yet).
int stop_signal();

/// "SIGTERM", "SIGINT".
const char* signal_name(int number);

/// Ends the process as that signal would have, once the command stopped cleanly: a shell, Slurm or
/// a parent sees a process killed by it (exit status 128 + its number), as without the handlers.
[[noreturn]] void end_by_signal(int number);

}  // namespace olt
