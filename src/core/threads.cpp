#include "olt/core/threads.h"

#include <sched.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "olt/core/error.h"

namespace olt {
namespace {

std::optional<std::string> first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  if (!in || !std::getline(in, line)) return std::nullopt;
  return line;
}

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

// The tightest quota of the cgroup `path` below `root` and of each of its parents up to `root`.
template <class Read>
std::optional<double> tightest(const fs::path& root, const std::string& path, Read read) {
  std::optional<double> best = read(root);
  fs::path folder = root;
  for (const auto& part : fs::path(path).relative_path()) {
    if (part.empty() || part == ".") continue;
    folder /= part;
    if (const auto q = read(folder); q && (!best || *q < *best)) best = q;
  }
  return best;
}

// The CPU quota of this process's cgroups, v2 ("0::/path") or v1 (a line naming the cpu controller).
std::optional<double> cgroup_quota(const CpuSources& s) {
  std::ifstream in(s.proc_self_cgroup);
  std::string line;
  std::optional<double> best;
  const auto take = [&](std::optional<double> q) {
    if (q && (!best || *q < *best)) best = q;
  };
  while (std::getline(in, line)) {
    const auto first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1), path = line.substr(second + 1);
    if (line.compare(0, first, "0") == 0 && controllers.empty()) {
      take(tightest(s.cgroup_root, path, v2_quota));
    } else {
      std::istringstream names(controllers);
      for (std::string name; std::getline(names, name, ',');)
        if (name == "cpu") {
          // v1 mounts the controller as cpu, or cpu,cpuacct (whichever exists).
          for (const char* mount : {"cpu", "cpu,cpuacct", "cpuacct,cpu"})
            if (fs::exists(s.cgroup_root / mount)) take(tightest(s.cgroup_root / mount, path, v1_quota));
        }
    }
  }
  return best;
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
