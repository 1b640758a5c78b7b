#include <csignal>

#include "olt/cli/commands.h"
#include "olt/core/allocator.h"

int main(int argc, char** argv) {
  olt::keep_freed_memory();
  // Past a file-size limit (ulimit -f) a write fails with EFBIG, reported with the file's name,
  // instead of the process being killed by SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
  return olt::run_cli(std::vector<std::string>(argv + 1, argv + argc));
}
