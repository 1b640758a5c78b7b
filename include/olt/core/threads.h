#pragma once
// How many threads olt works with: the CPUs this process may use, which on a cluster is less than
// the machine has. The affinity mask (taskset, Slurm's task/affinity, Kubernetes' static CPU
// manager), the cgroup's CPU quota (Kubernetes limits, Slurm's cgroup, docker --cpus: v2 cpu.max or
// v1 cpu.cfs_quota_us / cpu.cfs_period_us, the tightest of the process's cgroup and its parents) and
// SLURM_CPUS_PER_TASK each cap it; OLT_THREADS overrides all of them.
#include <cstddef>
#include <optional>
#include <string>

#include "olt/core/fs.h"

namespace olt {

/// Where the limits are read from (tests point them at folders of their own).
struct CpuSources {
  fs::path proc_self_cgroup = "/proc/self/cgroup";
  fs::path cgroup_root = "/sys/fs/cgroup";
  size_t affinity = 0;                     ///< CPUs in the affinity mask; 0: read it (sched_getaffinity)
  std::optional<std::string> slurm_cpus;   ///< SLURM_CPUS_PER_TASK; nullopt: read the environment
  std::optional<std::string> olt_threads;  ///< OLT_THREADS; nullopt: read the environment
};

struct ThreadCount {
  size_t threads = 1;
  std::string why;  ///< "2 CPUs in the affinity mask", "cgroup CPU quota 1.5", "OLT_THREADS=3", ...
};

/// Throws InputError naming OLT_THREADS when it is not a whole number from 1 to 1024.
ThreadCount usable_threads(const CpuSources& sources = {});

/// Sizes the process's thread pool (TBB, which OpenCV shares) to usable_threads(); call once,
/// first thing in main. Returns what it chose.
ThreadCount configure_threads();

}  // namespace olt
