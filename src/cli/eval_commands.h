#pragma once
// The evaluations of `olt eval`, one file each: eval_command.cpp (the command, poses),
// eval_labels_command.cpp (labels).
#include <set>
#include <string>

#include "args.h"

namespace olt {

/// Flags of one evaluation: the eval command's table entry accepts those of all of them.
void check_flags(const Args& args, const std::string& evaluation, const std::set<std::string>& accepted);

/// `olt eval labels A B`: the agreement of two labelings of one recording.
int eval_labels(const Args& args);

}  // namespace olt
