// The cache lock: exclusive between processes, and released by the kernel when its holder dies.
#include "olt/cache/lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <thread>

#include "support/temp_dir.h"

TEST_CASE("a cache lock held by a process that is killed is free again") {
  olt::test::TempDir dir;
  const auto file = dir / "locks/stage-ab.lock";
  { olt::CacheLock create(dir.path(), "stage-ab", nullptr); }  // creates the folder and file
  int ready[2];
  REQUIRE(::pipe(ready) == 0);
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {  // only system calls below: the test process has threads
    const int fd = ::open(file.c_str(), O_RDWR);
    if (fd < 0 || ::flock(fd, LOCK_EX) != 0) ::_exit(1);
    char byte = 1;
    if (::write(ready[1], &byte, 1) != 1) ::_exit(1);
    for (;;) ::pause();
  }
  char byte = 0;
  REQUIRE(::read(ready[0], &byte, 1) == 1);

  bool waited = false;
  std::thread killer([child] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ::kill(child, SIGKILL);
  });
  const auto start = std::chrono::steady_clock::now();
  {
    olt::CacheLock lock(dir.path(), "stage-ab", [&] { waited = true; });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK(waited);           // the child held it
    CHECK(seconds >= 0.15);  // and we got it only once the child was gone
    CHECK(seconds < 10);
    // Held now: another open file description cannot take it.
    const int fd = ::open(file.c_str(), O_RDWR);
    CHECK(::flock(fd, LOCK_EX | LOCK_NB) != 0);
    ::close(fd);
  }
  killer.join();
  ::waitpid(child, nullptr, 0);
  ::close(ready[0]);
  ::close(ready[1]);
}
