#include "olt/cache/lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace olt {

CacheLock::CacheLock(const std::filesystem::path& cache_root, const std::string& name,
                     const std::function<void()>& on_wait, bool shared) {
  const int mode = shared ? LOCK_SH : LOCK_EX;
  const std::filesystem::path file = cache_root / "locks" / (name + ".lock");
  std::filesystem::create_directories(file.parent_path());
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(file.string() + ": cannot open lock file: " + std::strerror(errno));
  if (::flock(fd_, mode | LOCK_NB) == 0) return;
  if (errno == EWOULDBLOCK && on_wait) on_wait();
  while (::flock(fd_, mode) != 0) {
    if (errno == EINTR) continue;
    const int error = errno;
    ::close(fd_);
    throw std::runtime_error(file.string() + ": cannot lock: " + std::strerror(error));
  }
}

CacheLock::~CacheLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

}  // namespace olt
