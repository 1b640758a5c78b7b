// How much memory the process may use: the machine's, or a cgroup's limit where tighter (v2 and v1,
// the tightest of the process's cgroup and its parents). On cgroup folders and a meminfo the test
// writes.
#include "olt/core/usable_memory.h"

#include <catch2/catch.hpp>

#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

constexpr uint64_t kGiB = uint64_t{1} << 30;

MemorySources sources(const TempDir& dir) {
  MemorySources s;
  s.proc_self_cgroup = dir / "proc_self_cgroup";
  s.cgroup_root = dir / "cgroup";
  s.meminfo = dir / "meminfo";
  return s;
}

}  // namespace

TEST_CASE("usable memory: the machine's, unless a cgroup v2 limit of the process's cgroup or a parent is tighter") {
  TempDir dir;
  write_text(dir / "meminfo", "MemTotal:       25165824 kB\nMemFree:         1000 kB\n");  // 24 GiB
  write_text(dir / "proc_self_cgroup", "0::/kubepods/pod1/container\n");
  write_text(dir / "cgroup/kubepods/pod1/container/memory.max", "max\n");
  MemoryAmount amount = usable_memory(sources(dir));
  CHECK(amount.bytes == 24 * kGiB);
  CHECK(amount.why == "the machine's 24.0 GB");

  write_text(dir / "cgroup/kubepods/pod1/memory.max", std::to_string(2 * kGiB) + "\n");
  write_text(dir / "cgroup/kubepods/memory.max", std::to_string(8 * kGiB) + "\n");
  amount = usable_memory(sources(dir));
  CHECK(amount.bytes == 2 * kGiB);
  CHECK(amount.why == "the cgroup's memory limit (2.0 GB)");
  // The parent's limit where the process's cgroup's is looser; a limit above the machine's leaves
  // the machine's.
  write_text(dir / "cgroup/kubepods/pod1/memory.max", std::to_string(64 * kGiB) + "\n");
  CHECK(usable_memory(sources(dir)).bytes == 8 * kGiB);
  write_text(dir / "cgroup/kubepods/memory.max", "max\n");
  CHECK(usable_memory(sources(dir)).bytes == 24 * kGiB);
  // What is not a whole number of bytes is no limit.
  for (const char* odd : {"nan", "1e9", " 5", "0x10", "-1", ""}) {
    CAPTURE(odd);
    write_text(dir / "cgroup/kubepods/pod1/memory.max", std::string(odd) + "\n");
    CHECK(usable_memory(sources(dir)).bytes == 24 * kGiB);
  }
}

TEST_CASE("usable memory: a cgroup v1 limit, its 'no limit' none - nothing readable gives 0") {
  TempDir dir;
  write_text(dir / "meminfo", "HugePages_Total:       0\nMemTotal:       4194304 kB\n");  // 4 GiB, not first
  write_text(dir / "proc_self_cgroup", "12:memory:/slurm/job7\n4:cpu,cpuacct:/\n");
  write_text(dir / "cgroup/memory/slurm/job7/memory.limit_in_bytes", "1073741824\n");
  write_text(dir / "cgroup/memory/memory.limit_in_bytes", "9223372036854771712\n");  // v1's "no limit"
  CHECK(usable_memory(sources(dir)).bytes == kGiB);
  write_text(dir / "cgroup/memory/slurm/job7/memory.limit_in_bytes", "9223372036854771712\n");
  CHECK(usable_memory(sources(dir)).bytes == 4 * kGiB);
  write_text(dir / "meminfo", "nothing here\n");
  CHECK(usable_memory(sources(dir)).bytes == 0);
  CHECK(usable_memory(sources(dir)).why.empty());
}
