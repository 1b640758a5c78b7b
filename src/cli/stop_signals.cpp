#include "stop_signals.h"

#include <unistd.h>

#include <csignal>
#include <cstdlib>

namespace olt {
namespace {

static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free,
              "set from a signal handler");

std::atomic<bool> stop_requested{false};
std::atomic<int> stopped_by{0};

// Ends the process by `number` from inside its handler: the default action put back and the signal
// (blocked while its handler runs) let through. Only async-signal-safe calls.
void end_now(int number) {
  std::signal(number, SIG_DFL);
  sigset_t just_it;
  sigemptyset(&just_it);
  sigaddset(&just_it, number);
  pthread_sigmask(SIG_UNBLOCK, &just_it, nullptr);
  raise(number);
  _exit(128 + number);  // where the default action is ignored: a container's PID 1
}

// The first SIGINT or SIGTERM asks for a stop; a second one, of either, ends the process at once.
void request_stop(int number) {
  int none = 0;  // the first signal's number kept, before the flag the run reads first
  if (!stopped_by.compare_exchange_strong(none, number)) end_now(number);
  stop_requested = true;
}

}  // namespace

const std::atomic<bool>& stop_on_signals() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  // Most blocking calls the signal interrupts are restarted, so that libraries' reads and waits
  // need not know about EINTR (poll, nanosleep and a few others return it all the same).
  action.sa_flags = SA_RESTART;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  return stop_requested;
}

int stop_signal() { return stopped_by; }

const char* signal_name(int number) { return number == SIGINT ? "SIGINT" : number == SIGTERM ? "SIGTERM" : "a signal"; }

void end_by_signal(int number) {
  std::signal(number, SIG_DFL);
  std::raise(number);
  // Reached where the default action is ignored: olt as a container's PID 1 (`ENTRYPOINT ["olt"]`),
  // which the kernel does not end by signals sent from inside its container.
  std::_Exit(128 + number);
}

}  // namespace olt
