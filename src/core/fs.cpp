#include "olt/core/fs.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "olt/core/error.h"

namespace olt {

std::string read_file(const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file.string(), "file not found");
  if (fs::is_directory(file, ec)) throw InputError(file.string(), "expected a file, found a folder");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "cannot open file for reading");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw InputError(file.string(), "read error");
  return bytes.str();
}

fs::path temp_sibling(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() /
         (".tmp." + target.filename().string() + "." + std::to_string(::getpid()) + "." + std::to_string(counter++));
}

void write_file_atomic(const fs::path& file, std::string_view bytes) {
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  const fs::path temp = temp_sibling(file);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(temp.string() + ": cannot create: " + std::strerror(errno));
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string reason = std::strerror(errno);
      ::close(fd);
      fs::remove(temp);
      throw std::runtime_error(file.string() + ": write failed: " + reason);
    }
    written += static_cast<size_t>(n);
  }
  // Data on disk before the rename makes it visible: a crash leaves the old file or the new one.
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    fs::remove(temp);
    throw std::runtime_error(file.string() + ": write failed: " + std::strerror(errno));
  }
  fs::rename(temp, file);
}

void write_file(const fs::path& file, std::string_view bytes) {
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error(file.string() + ": write failed: " + std::strerror(errno));
}

void sync_file_system(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path.string() + ": cannot open to sync: " + std::strerror(errno));
  const int result = ::syncfs(fd);
  const int error = errno;
  ::close(fd);
  if (result != 0) throw std::runtime_error(path.string() + ": sync failed: " + std::strerror(error));
}

fs::path resolve_path(const fs::path& base, const fs::path& path) {
  return (path.is_absolute() ? path : base / path).lexically_normal();
}

}  // namespace olt
