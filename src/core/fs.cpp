#include "olt/core/fs.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <sstream>
#include <system_error>
#include <vector>

#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/huge_pages.h"

namespace olt {

int open_regular_file(const fs::path& file, uint64_t* size) {
  // Without blocking: opening a FIFO for reading would wait for a writer forever.
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    const int error = errno;
    if (error == ENOENT) throw InputError(file.string(), "file not found");
    if (error == ELOOP) throw InputError(file.string(), "symbolic link loop");
    throw InputError(file.string(), std::string("cannot open file for reading: ") + std::strerror(error));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw InputError(file.string(), S_ISDIR(st.st_mode)    ? "expected a file, found a folder"
                                    : S_ISFIFO(st.st_mode) ? "not a regular file (a named pipe)"
                                                           : "not a regular file");
  }
  ::fcntl(fd, F_SETFL, 0);  // blocking again (its one status flag was O_NONBLOCK): one call, not two
  *size = static_cast<uint64_t>(st.st_size);
  return fd;
}

namespace {

std::string read_up_to(const fs::path& file, int fd, size_t count) {
  std::string bytes;
  bytes.reserve(count);
  advise_huge_pages(bytes.data(), count);  // before the pages are first written: a large file's read
  bytes.resize(count);
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      throw InputError(file.string(), std::string("read error: ") + std::strerror(error));
    }
    if (n == 0) break;  // shorter than expected (it shrank while being read)
    done += static_cast<size_t>(n);
  }
  ::close(fd);
  bytes.resize(done);
  return bytes;
}

}  // namespace

namespace {

// A file descriptor's bytes through a buffer: what open_file_stream hands out (owns the descriptor).
class FileStreamBuffer : public std::streambuf {
 public:
  FileStreamBuffer(fs::path file, int fd) : file_(std::move(file)), fd_(fd) {}
  ~FileStreamBuffer() override { ::close(fd_); }
  FileStreamBuffer(const FileStreamBuffer&) = delete;
  FileStreamBuffer& operator=(const FileStreamBuffer&) = delete;

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    ssize_t n = 0;
    do n = ::read(fd_, buffer_.data(), buffer_.size());
    while (n < 0 && errno == EINTR);
    if (n < 0) throw InputError(file_.string(), std::string("read error: ") + std::strerror(errno));
    if (n == 0) return traits_type::eof();
    setg(buffer_.data(), buffer_.data(), buffer_.data() + n);
    return traits_type::to_int_type(*gptr());
  }

 private:
  fs::path file_;
  int fd_;
  std::vector<char> buffer_ = std::vector<char>(64 << 10);
};

// An istream that owns its buffer.
class FileStream : public std::istream {
 public:
  FileStream(fs::path file, int fd) : std::istream(nullptr), buffer_(std::move(file), fd) { rdbuf(&buffer_); }

 private:
  FileStreamBuffer buffer_;
};

}  // namespace

std::unique_ptr<std::istream> open_file_stream(const fs::path& file) {
  uint64_t size = 0;
  const int fd = open_regular_file(file, &size);
  return std::make_unique<FileStream>(file, fd);
}

std::string read_file_head(const fs::path& file, size_t count) {
  uint64_t size = 0;
  const int fd = open_regular_file(file, &size);
  return read_up_to(file, fd, static_cast<size_t>(std::min<uint64_t>(size, count)));
}

std::string read_file(const fs::path& file) {
  uint64_t size = 0;
  const int fd = open_regular_file(file, &size);
  if (size > kMaxInputFileBytes) {
    ::close(fd);
    throw InputError(file.string(), "is " + std::to_string(size >> 20) + " MB; input files are read whole, at most " +
                                        std::to_string(kMaxInputFileBytes >> 20) + " MB");
  }
  return read_up_to(file, fd, static_cast<size_t>(size));
}

const std::string& host_name() {
  static const std::string name = [] {
    char text[256] = {};
    if (::gethostname(text, sizeof(text) - 1) != 0 || !text[0]) return std::string("host");
    std::string clean(text);
    for (char& c : clean)  // a field of file names: no dots or slashes in it
      if (c == '.' || c == '/') c = '-';
    return clean;
  }();
  return name;
}

fs::path temp_sibling(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() / (".tmp." + target.filename().string() + "." + host_name() + "." +
                                 std::to_string(::getpid()) + "." + std::to_string(counter++));
}

int write_fully(int fd, std::string_view bytes) {
  if (const int injected = injected_write_error()) return injected;
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno;
    if (n == 0) return ENOSPC;
    written += static_cast<size_t>(n);
  }
  return 0;
}

void write_file_atomic(const fs::path& file, std::string_view bytes) {
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  const fs::path temp = temp_sibling(file);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(temp.string() + ": cannot create: " + std::strerror(errno));
  if (const int error = write_fully(fd, bytes)) {
    ::close(fd);
    fs::remove(temp);
    throw std::runtime_error(file.string() + ": write failed: " + std::strerror(error));
  }
  // Data on disk before the rename makes it visible: a crash leaves the old file or the new one.
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    fs::remove(temp);
    throw std::runtime_error(file.string() + ": write failed: " + std::strerror(errno));
  }
  fs::rename(temp, file);
}

void sync_file_systems(const std::vector<fs::path>& paths) {
  std::vector<dev_t> synced;
  for (const fs::path& path : paths) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(path.string() + ": cannot open to sync: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) == 0 && std::find(synced.begin(), synced.end(), st.st_dev) != synced.end()) {
      ::close(fd);
      continue;  // its file system is synced already
    }
    const int result = ::syncfs(fd);
    const int error = errno;
    ::close(fd);
    if (result != 0) throw std::system_error(error, std::generic_category(), path.string() + ": sync failed");
    synced.push_back(st.st_dev);
  }
}

fs::path resolve_path(const fs::path& base, const fs::path& path) {
  return (path.is_absolute() ? path : base / path).lexically_normal();
}

namespace {

// Whether none of `path`'s parts between slashes is one `refused` refuses: without making a path of
// it (publishing checks 80,000 twice).
template <class Refused>
bool no_part(std::string_view path, const Refused& refused) {
  for (size_t begin = 0; begin <= path.size();) {
    const size_t end = std::min(path.find('/', begin), path.size());
    if (refused(path.substr(begin, end - begin))) return false;
    begin = end + 1;
  }
  return true;
}

}  // namespace

bool stays_inside(std::string_view path) {
  return !path.empty() && path.front() != '/' &&
         no_part(path, [](std::string_view part) { return part == "." || part == ".."; });
}

std::string_view folder_of(std::string_view path) {
  const size_t slash = path.rfind('/');
  return path.substr(0, slash == std::string_view::npos ? 0 : slash);
}

bool already_normal(std::string_view path) {
  return no_part(path, [](std::string_view part) { return part.empty() || part == "." || part == ".."; });
}

}  // namespace olt
