#include "olt/core/threads.h"

#include <sched.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "cgroups.h"
#include "olt/core/error.h"

namespace olt {
namespace {

// A quota in CPUs from cgroup v2's cpu.max ("max 100000" or "150000 100000").
std::optional<double> v2_quota(const fs::path& folder) {
  const auto line = first_line(folder / "cpu.max");
  if (!line) return std::nullopt;
  std::istringstream words(*line);
  std::string quota;
  double period = 0;
  if (!(words >> quota >> period) || quota == "max" || period <= 0) return std::nullopt;
  char* end = nullptr;
  const double q = std::strtod(quota.c_str(), &end);
  if (*end != '\0' || q <= 0) return std::nullopt;
  return q / period;
}

// cgroup v1: cpu.cfs_quota_us (-1: none) over cpu.cfs_period_us.
std::optional<double> v1_quota(const fs::path& folder) {
  const auto quota = first_line(folder / "cpu.cfs_quota_us"), period = first_line(folder / "cpu.cfs_period_us");
  if (!quota || !period) return std::nullopt;
  const double q = std::atof(quota->c_str()), p = std::atof(period->c_str());
  if (q <= 0 || p <= 0) return std::nullopt;
  return q / p;
}

// The CPU quota of this process's cgroups.
std::optional<double> cgroup_quota(const CpuSources& s) {
  // v1 mounts the controller as cpu, or cpu,cpuacct (whichever exists).
  return cgroup_limit(s.proc_self_cgroup, s.cgroup_root,
                      {v2_quota, "cpu", {"cpu", "cpu,cpuacct", "cpuacct,cpu"}, v1_quota});
}

size_t affinity_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0)  // more CPUs than a cpu_set_t holds (1024)
    return std::max(1u, std::thread::hardware_concurrency());
  return static_cast<size_t>(std::max(1, CPU_COUNT(&set)));
}

std::optional<std::string> from_environment(const std::optional<std::string>& given, const char* name) {
  if (given) return given;
  const char* value = std::getenv(name);
  if (!value) return std::nullopt;
  return std::string(value);
}

}  // namespace

ThreadCount usable_threads(const CpuSources& s) {
  if (const auto given = from_environment(s.olt_threads, "OLT_THREADS"); given && !given->empty()) {
    char* end = nullptr;
    const long n = std::strtol(given->c_str(), &end, 10);
    if (*end != '\0' || n < 1 || n > 1024)
      throw InputError("OLT_THREADS", "expected a whole number from 1 to 1024 (threads), got '" + *given + "'");
    return {static_cast<size_t>(n), "OLT_THREADS=" + *given};
  }
  ThreadCount count{s.affinity ? s.affinity : affinity_cpus(), ""};
  count.why = std::to_string(count.threads) + " CPUs in the affinity mask";
  if (const auto quota = cgroup_quota(s)) {
    const size_t cpus = static_cast<size_t>(std::max(1.0, std::ceil(*quota - 1e-9)));
    if (cpus < count.threads) {
      char text[64];
      std::snprintf(text, sizeof(text), "the cgroup's CPU quota (%.2f CPUs)", *quota);
      count = {cpus, text};
    }
  }
  if (const auto slurm = from_environment(s.slurm_cpus, "SLURM_CPUS_PER_TASK")) {
    char* end = nullptr;
    const long n = std::strtol(slurm->c_str(), &end, 10);
    if (*end == '\0' && n >= 1 && static_cast<size_t>(n) < count.threads)
      count = {static_cast<size_t>(n), "SLURM_CPUS_PER_TASK=" + *slurm};
  }
  return count;
}

ThreadCount configure_threads() {
  const ThreadCount count = usable_threads();
  static std::unique_ptr<tbb::global_control> limit;
  limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, count.threads);
  cv::setNumThreads(static_cast<int>(count.threads));
  return count;
}

}  // namespace olt
