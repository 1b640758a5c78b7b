#include "support/process.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <stdexcept>
#include <thread>

#include "support/temp_dir.h"

namespace olt::test {

OltProcess::OltProcess(const std::vector<std::string>& args, const std::filesystem::path& log_dir,
                       const std::vector<std::string>& environment)
    : log_dir_(log_dir) {
  std::filesystem::create_directories(log_dir);
  const std::string out = (log_dir / "stdout").string(), err = (log_dir / "stderr").string();
  std::vector<std::string> words = {OLT_BINARY};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const pid_t parent = ::getpid();
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);
    const int out_fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err_fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out_fd, 1);
    ::dup2(err_fd, 2);
    for (const std::string& variable : environment) ::putenv(const_cast<char*>(variable.c_str()));
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
}

OltProcess::~OltProcess() {
  if (pid_ > 0) stop(SIGKILL, 5);
}

bool OltProcess::running() {
  if (pid_ <= 0) return false;
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) == 0) return true;
  pid_ = -1;  // exited (and reaped)
  exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  died_of_ = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  return false;
}

int OltProcess::stop(int signal, double timeout_s) {
  if (pid_ <= 0) return exit_code_;
  ::kill(pid_, signal);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  int status = 0;
  while (::waitpid(pid_, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > until) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
      pid_ = -1;
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  pid_ = -1;
  died_of_ = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  return exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string OltProcess::err() const { return read_text(log_dir_ / "stderr"); }

bool OltProcess::said(const std::string& text, double timeout_s) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    const bool was_running = running();  // before reading: what it wrote before it ended is read
    if (err().find(text) != std::string::npos) return true;
    if (!was_running || std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace olt::test
