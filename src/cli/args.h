#pragma once
// Parsed command-line arguments and the subcommands defined outside commands.cpp (private to cli/).
#include <map>
#include <string>
#include <vector>

namespace olt {

struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> flags;  ///< "--json" -> "", "--max-dt" -> "0.02"
  bool has(const std::string& flag) const { return flags.count(flag) > 0; }
  std::string value(const std::string& flag, const std::string& fallback) const {
    auto it = flags.find(flag);
    return it == flags.end() ? fallback : it->second;
  }
};

int cmd_eval(const Args& args);
int cmd_boxes(const Args& args);
int cmd_cache(const Args& args);
int cmd_watch(const Args& args);
/// `olt help KIND`: prints the stage kind's parameters; false when there is no kind of that name.
bool print_kind_help(const std::string& name);

}  // namespace olt
