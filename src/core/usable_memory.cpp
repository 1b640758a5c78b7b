#include "olt/core/usable_memory.h"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>

#include "cgroups.h"

namespace olt {
namespace {

// A byte count from a limit file's line: "max" (v2) and v1's "no limit" (the largest page-aligned
// 64-bit count, 2^63 - 4096, or so) are none, and so is anything but a whole number.
std::optional<double> limit_bytes(const std::optional<std::string>& line) {
  if (!line) return std::nullopt;
  uint64_t bytes = 0;
  const char* end = line->data() + line->size();
  const auto [at, error] = std::from_chars(line->data(), end, bytes);
  if (error != std::errc() || at != end || bytes == 0 || bytes >= (uint64_t{1} << 62)) return std::nullopt;
  return static_cast<double>(bytes);
}

std::optional<double> v2_limit(const fs::path& folder) { return limit_bytes(first_line(folder / "memory.max")); }
std::optional<double> v1_limit(const fs::path& folder) {
  return limit_bytes(first_line(folder / "memory.limit_in_bytes"));
}

// The machine's memory, from /proc/meminfo's line "MemTotal:       24605520 kB"; 0 without one.
uint64_t machine_bytes(const fs::path& meminfo) {
  std::ifstream in(meminfo);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string name, unit;
    uint64_t amount = 0;
    if (words >> name >> amount && name == "MemTotal:") return (words >> unit && unit == "kB") ? amount * 1024 : amount;
  }
  return 0;
}

std::string gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f GB", bytes / double(1ull << 30));
  return text;
}

}  // namespace

MemoryAmount usable_memory(const MemorySources& s) {
  MemoryAmount amount{machine_bytes(s.meminfo), ""};
  if (amount.bytes) amount.why = "the machine's " + gigabytes(static_cast<double>(amount.bytes));
  const auto limit = cgroup_limit(s.proc_self_cgroup, s.cgroup_root, {v2_limit, "memory", {"memory"}, v1_limit});
  if (limit && (!amount.bytes || *limit < static_cast<double>(amount.bytes)))
    amount = {static_cast<uint64_t>(*limit), "the cgroup's memory limit (" + gigabytes(*limit) + ")"};
  return amount;
}

}  // namespace olt
