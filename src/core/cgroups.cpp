#include "cgroups.h"

#include <fstream>
#include <sstream>

namespace olt {
namespace {

// The tightest limit of the cgroup `path` below `root` and of each of its parents up to `root`.
std::optional<double> tightest(const fs::path& root, const std::string& path,
                               const std::function<std::optional<double>(const fs::path&)>& read) {
  std::optional<double> best = read(root);
  fs::path folder = root;
  for (const auto& part : fs::path(path).relative_path()) {
    if (part.empty() || part == ".") continue;
    folder /= part;
    if (const auto q = read(folder); q && (!best || *q < *best)) best = q;
  }
  return best;
}

}  // namespace

std::optional<std::string> first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  if (!in || !std::getline(in, line)) return std::nullopt;
  return line;
}

std::optional<double> cgroup_limit(const fs::path& proc_self_cgroup, const fs::path& cgroup_root,
                                   const CgroupLimit& limit) {
  std::ifstream in(proc_self_cgroup);
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
      take(tightest(cgroup_root, path, limit.v2));
    } else {
      std::istringstream names(controllers);
      for (std::string name; std::getline(names, name, ',');)
        if (name == limit.v1_controller)
          for (const std::string& mount : limit.v1_mounts)  // whichever of its mounts exists
            if (fs::exists(cgroup_root / mount)) take(tightest(cgroup_root / mount, path, limit.v1));
    }
  }
  return best;
}

}  // namespace olt
