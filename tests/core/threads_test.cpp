// How many threads: the affinity mask, the cgroup's CPU quota (v2 and v1, the tightest of the
// process's cgroup and its parents), SLURM_CPUS_PER_TASK, and OLT_THREADS over all of them; on
// cgroup folders the test writes.
#include "olt/core/threads.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

CpuSources sources(const TempDir& dir, size_t affinity) {
  CpuSources s;
  s.proc_self_cgroup = dir / "proc_self_cgroup";
  s.cgroup_root = dir / "cgroup";
  s.affinity = affinity;
  s.slurm_cpus = "";
  s.olt_threads = "";
  return s;
}

}  // namespace

TEST_CASE("threads: the affinity mask when nothing else limits") {
  TempDir dir;
  write_text(dir / "proc_self_cgroup", "0::/user.slice\n");
  write_text(dir / "cgroup/user.slice/cpu.max", "max 100000\n");
  const ThreadCount count = usable_threads(sources(dir, 8));
  CHECK(count.threads == 8);
  CHECK(count.why == "8 CPUs in the affinity mask");
}

TEST_CASE("threads: a cgroup v2 quota of the process's cgroup or a parent caps them, rounded up") {
  TempDir dir;
  write_text(dir / "proc_self_cgroup", "0::/kubepods/pod1/container\n");
  write_text(dir / "cgroup/kubepods/pod1/container/cpu.max", "max 100000\n");
  write_text(dir / "cgroup/kubepods/pod1/cpu.max", "250000 100000\n");  // 2.5 CPUs
  write_text(dir / "cgroup/kubepods/cpu.max", "800000 100000\n");
  const ThreadCount count = usable_threads(sources(dir, 16));
  CHECK(count.threads == 3);
  CHECK(count.why == "the cgroup's CPU quota (2.50 CPUs)");
  // A quota above the affinity leaves the affinity; half a CPU still gets one thread.
  CHECK(usable_threads(sources(dir, 2)).threads == 2);
  write_text(dir / "cgroup/kubepods/pod1/container/cpu.max", "50000 100000\n");
  CHECK(usable_threads(sources(dir, 16)).threads == 1);
}

TEST_CASE("threads: a cgroup v1 cfs quota, under a cgroup namespace's root") {
  TempDir dir;
  write_text(dir / "proc_self_cgroup", "12:memory:/\n4:cpu,cpuacct:/\n1:name=systemd:/\n");
  write_text(dir / "cgroup/cpu,cpuacct/cpu.cfs_quota_us", "200000\n");
  write_text(dir / "cgroup/cpu,cpuacct/cpu.cfs_period_us", "100000\n");
  CHECK(usable_threads(sources(dir, 64)).threads == 2);
  write_text(dir / "cgroup/cpu,cpuacct/cpu.cfs_quota_us", "-1\n");  // no quota
  CHECK(usable_threads(sources(dir, 64)).threads == 64);
}

TEST_CASE("threads: SLURM_CPUS_PER_TASK caps them, OLT_THREADS overrides all, a bad OLT_THREADS is refused") {
  TempDir dir;
  write_text(dir / "proc_self_cgroup", "0::/\n");
  write_text(dir / "cgroup/cpu.max", "400000 100000\n");
  CpuSources s = sources(dir, 32);
  s.slurm_cpus = "3";
  CHECK(usable_threads(s).threads == 3);
  CHECK(usable_threads(s).why == "SLURM_CPUS_PER_TASK=3");
  s.olt_threads = "12";
  CHECK(usable_threads(s).threads == 12);
  CHECK(usable_threads(s).why == "OLT_THREADS=12");
  for (const char* bad : {"0", "two", "2.5", "-1", "5000"}) {
    s.olt_threads = bad;
    INFO(bad);
    CHECK_THROWS_WITH(usable_threads(s),
                      Catch::Contains("OLT_THREADS") && Catch::Contains("expected a whole number from 1 to 1024"));
  }
}

TEST_CASE(
    "threads: a bad OLT_THREADS stops a command that computes with exit 2 naming it - help and version still work") {
  ::setenv("OLT_THREADS", "many", 1);
  const auto run = run_olt("validate missing.yaml");
  const auto version = run_olt("version");
  const auto help = run_olt("help run");
  ::unsetenv("OLT_THREADS");
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Catch::Contains("OLT_THREADS") && Catch::Contains("got 'many'"));
  CHECK(version.exit_code == 0);
  CHECK(help.exit_code == 0);
  CHECK_THAT(help.out, Catch::Contains("usage: olt run"));
}
