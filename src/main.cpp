#include "olt/cli/commands.h"
#include "olt/core/allocator.h"

int main(int argc, char** argv) {
  olt::keep_freed_memory();
  return olt::run_cli(std::vector<std::string>(argv + 1, argv + argc));
}
