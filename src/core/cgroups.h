#pragma once
// A limit the kernel's control groups put on this process: the tightest of its cgroup's and each
// parent's, v2 (the unified hierarchy, "0::/path" in /proc/self/cgroup) or v1 (a hierarchy per
// controller). How many CPUs (threads.cpp) and how much memory (usable_memory.cpp) it may use.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "olt/core/fs.h"

namespace olt {

/// The first line of `file`, nullopt where it cannot be read.
std::optional<std::string> first_line(const fs::path& file);

/// How one controller's limit is read from a cgroup's folder (nullopt: none there).
struct CgroupLimit {
  std::function<std::optional<double>(const fs::path&)> v2;
  std::string v1_controller;           ///< "cpu", "memory"
  std::vector<std::string> v1_mounts;  ///< where v1 mounts it below the root ("cpu", "cpu,cpuacct")
  std::function<std::optional<double>(const fs::path&)> v1;
};

/// The tightest limit of the process's cgroups (`proc_self_cgroup` read, the hierarchy at
/// `cgroup_root`), nullopt where none is set.
std::optional<double> cgroup_limit(const fs::path& proc_self_cgroup, const fs::path& cgroup_root,
                                   const CgroupLimit& limit);

}  // namespace olt
