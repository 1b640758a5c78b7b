#pragma once
// The `olt` command line: every subcommand in one table (src/cli/commands.cpp).
#include <string>
#include <vector>

namespace olt {

/// Runs `olt ARGS...` and returns the exit code (see ExitCode in olt/core/error.h).
int run_cli(const std::vector<std::string>& args);

}  // namespace olt
