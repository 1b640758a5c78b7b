#pragma once
// How much memory this process may use: the machine's, or less where a control group limits it
// (Kubernetes limits, Slurm's cgroup, docker --memory: v2 memory.max or v1 memory.limit_in_bytes,
// the tightest of the process's cgroup and its parents). What `olt watch` sizes the memory it keeps
// between cycles from.
#include <cstdint>
#include <string>

#include "olt/core/fs.h"

namespace olt {

/// Where the limits are read from (tests point them at files of their own).
struct MemorySources {
  fs::path proc_self_cgroup = "/proc/self/cgroup";
  fs::path cgroup_root = "/sys/fs/cgroup";
  fs::path meminfo = "/proc/meminfo";
};

struct MemoryAmount {
  uint64_t bytes = 0;  ///< 0: neither could be read
  std::string why;     ///< "the machine's 23.5 GB", "the cgroup's memory limit (2.0 GB)"
};

MemoryAmount usable_memory(const MemorySources& sources = {});

}  // namespace olt
