#pragma once
// A background `olt` process for tests of the daemon: started with its output in files, stopped by
// a signal with a bounded wait, and killed when the test ends or the test process dies
// (PR_SET_PDEATHSIG), so no daemon outlives its test.
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace olt::test {

class OltProcess {
 public:
  /// Starts the built `olt` with `args`; stdout and stderr go to files in `log_dir`; `environment`
  /// ("NAME=value") is added to the test's own (e.g. olt/core/fault.h's fault points).
  OltProcess(const std::vector<std::string>& args, const std::filesystem::path& log_dir,
             const std::vector<std::string>& environment = {});
  ~OltProcess();
  OltProcess(const OltProcess&) = delete;
  OltProcess& operator=(const OltProcess&) = delete;

  /// Sends `signal` (0: none) and waits up to `timeout_s` for the exit; returns the exit code, or -1
  /// when it did not exit in time (it is then killed) or died of a signal.
  int stop(int signal, double timeout_s);
  bool running();
  std::string err() const;  ///< what it wrote to stderr so far
  /// Whether its stderr holds `text`, waiting up to `timeout_s` for it while it runs.
  bool said(const std::string& text, double timeout_s);
  int died_of() const { return died_of_; }  ///< the signal that ended it, once it ended (0: none)

 private:
  pid_t pid_ = -1;
  int exit_code_ = -1;  ///< once reaped
  int died_of_ = 0;
  std::filesystem::path log_dir_;
};

}  // namespace olt::test
