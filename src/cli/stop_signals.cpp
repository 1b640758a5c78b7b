#include "stop_signals.h"

#include <csignal>
#include <cstdlib>

namespace olt {
namespace {

std::atomic<bool> stop_requested{false};
std::atomic<int> stopped_by{0};

void request_stop(int signal) {
  stopped_by = signal;
  stop_requested = true;
}

}  // namespace

const std::atomic<bool>& stop_on_signals() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  // The second signal takes its default action, ending the process; a system call the signal
  // interrupts is restarted (libraries' reads and waits need not know about EINTR).
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  return stop_requested;
}

int stop_signal() { return stopped_by; }

const char* signal_name(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal"; }

void end_by_signal(int signal) {
  std::signal(signal, SIG_DFL);
  std::raise(signal);
  std::_Exit(128 + signal);  // not reached: the default action of SIGINT and SIGTERM ends the process
}

}  // namespace olt
