#include "olt/cli/commands.h"

int main(int argc, char** argv) { return olt::run_cli(std::vector<std::string>(argv + 1, argv + argc)); }
