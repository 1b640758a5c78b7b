// The machine's file system behind FileSystem, and what every file system shares.
#include "olt/core/file_system.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <functional>
#include <sstream>

#include "olt/core/fault.h"
#include "olt/core/hash.h"

namespace olt {

std::string FileSystem::sha256(const fs::path& file) const { return sha256_hex(read(file)); }

std::string FileSystem::copy_hashed(const fs::path& from, const fs::path& to) {
  copy(from, to);
  return sha256(to);
}

bool replace_with(FileSystem& files, const fs::path& file, const std::function<void(const fs::path& temp)>& make) {
  const fs::path temp = temp_sibling(file);
  try {
    make(temp);
    if (files.rename(temp, file)) return true;
  } catch (...) {
    files.remove(temp);
    throw;
  }
  files.remove(temp);
  return false;
}

void FileSystem::write_atomic(const fs::path& file, std::string_view bytes) {
  if (!replace_with(*this, file, [&](const fs::path& temp) { write(temp, bytes); }))
    throw FileSystemError(file.string() + ": cannot replace: it is a folder");
}

std::unique_ptr<std::istream> FileSystem::read_stream(const fs::path& file) const {
  return std::make_unique<std::istringstream>(read(file));
}

std::vector<std::string> FileSystem::files_below(const fs::path& folder) const {
  std::vector<std::string> files;
  const std::function<void(const fs::path&, const std::string&)> walk = [&](const fs::path& dir,
                                                                            const std::string& prefix) {
    for (const auto& name : list(dir)) {
      const FileStat st = stat(dir / name);
      if (st.is_file()) files.push_back(prefix + name);
      if (st.is_folder()) walk(dir / name, prefix + name + "/");
    }
  };
  walk(folder, "");
  std::sort(files.begin(), files.end());
  return files;
}

namespace {

[[noreturn]] void fail(const fs::path& path, const std::string& what, int error) {
  throw FileSystemError(path.string() + ": " + what + ": " + std::strerror(error));
}

void write_all(const fs::path& file, int fd, std::string_view bytes) {
  if (const int error = write_fully(fd, bytes)) {
    ::close(fd);
    fail(file, "write failed", error);
  }
  if (::close(fd) != 0) fail(file, "write failed", errno);
}

// `file` opened for writing, created (0644) with its parent folders where they are missing: tried
// first, made only on failure, so that a folder already there costs no stat (a run writes 100,000
// files at 10,000 observations, and on a network file system each stat is a round trip).
template <typename Open>
int open_creating_folders(const fs::path& file, const Open& open) {
  int fd = open();
  if (fd < 0 && (errno == ENOENT || errno == ENOTDIR) && file.has_parent_path()) {
    real_file_system().make_folders(file.parent_path());  // throws, naming the folder, where it cannot
    fd = open();
  }
  return fd;
}

int create_file(const fs::path& file, int flags) {
  const int fd =
      open_creating_folders(file, [&] { return ::open(file.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | flags, 0644); });
  if (fd < 0) fail(file, "cannot create", errno);
  return fd;
}

void write_with(const fs::path& file, std::string_view bytes, int flags) {
  write_all(file, create_file(file, flags), bytes);
}

// Copies the bytes of `in` (open for reading) into `to`, created or truncated, hashing them on the
// way; closes `in`. Failures name `to` and `from`.
std::string copy_and_hash(int in, const fs::path& from, const fs::path& to) {
  const auto failed = [&](int error) -> std::string {
    throw FileSystemError(to.string() + ": cannot copy " + from.string() + ": " + std::strerror(error));
  };
  int out = -1;
  try {
    out = open_creating_folders(to, [&] { return ::open(to.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644); });
    if (out < 0) failed(errno);
    Sha256 hash;
    std::array<char, 1 << 16> buffer{};
    for (;;) {
      const ssize_t n = ::read(in, buffer.data(), buffer.size());
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) failed(errno);
      if (n == 0) break;
      const std::string_view piece(buffer.data(), static_cast<size_t>(n));
      hash.update(piece);
      if (const int error = write_fully(out, piece)) failed(error);
    }
    ::close(in);
    in = -1;
    const int closed = ::close(out);
    out = -1;
    if (closed != 0) failed(errno);
    return hash.hex();
  } catch (...) {
    if (in >= 0) ::close(in);
    if (out >= 0) ::close(out);
    throw;
  }
}

FileStat::Type type_of(mode_t mode) {
  if (S_ISREG(mode)) return FileStat::Type::file;
  if (S_ISDIR(mode)) return FileStat::Type::folder;
  if (S_ISLNK(mode)) return FileStat::Type::link;
  return FileStat::Type::other;
}

class FlockLock : public FileSystem::Lock {
 public:
  FlockLock(const fs::path& file, bool shared, const std::function<void()>& on_wait) {
    const int mode = shared ? LOCK_SH : LOCK_EX;
    if (file.has_parent_path()) real_file_system().make_folders(file.parent_path());
    fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) fail(file, "cannot open lock file", errno);
    if (::flock(fd_, mode | LOCK_NB) == 0) return;
    if (errno == EWOULDBLOCK && on_wait) on_wait();
    while (::flock(fd_, mode) != 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd_);
      fail(file, "cannot lock", error);
    }
  }
  ~FlockLock() override { ::close(fd_); }  // closing releases the lock
  FlockLock(const FlockLock&) = delete;
  FlockLock& operator=(const FlockLock&) = delete;

 private:
  int fd_ = -1;
};

class RealFileSystem : public FileSystem {
 public:
  std::string read(const fs::path& file) const override { return read_file(file); }
  std::unique_ptr<std::istream> read_stream(const fs::path& file) const override { return open_file_stream(file); }
  std::string sha256(const fs::path& file) const override { return sha256_file(file); }
  void write(const fs::path& file, std::string_view bytes) override { write_with(file, bytes, O_TRUNC); }
  void append(const fs::path& file, std::string_view bytes) override { write_with(file, bytes, O_APPEND); }
  void write_atomic(const fs::path& file, std::string_view bytes) override { write_file_atomic(file, bytes); }

  void link(const fs::path& from, const fs::path& to) override {
    if (to.has_parent_path()) make_folders(to.parent_path());
    std::error_code ec;
    fs::create_hard_link(from, to, ec);
    if (ec) copy(from, to);
  }

  void copy(const fs::path& from, const fs::path& to) override {
    if (const int error = injected_write_error()) fail(to, "cannot copy " + from.string(), error);
    std::error_code ec;
    const auto copy_file = [&] { return fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec); };
    if (!copy_file() && ec == std::errc::no_such_file_or_directory && to.has_parent_path() && fs::exists(from)) {
      make_folders(to.parent_path());  // tried first: a folder already there costs no stat
      copy_file();
    }
    if (ec) throw FileSystemError(to.string() + ": cannot copy " + from.string() + ": " + ec.message());
  }

  std::string copy_hashed(const fs::path& from, const fs::path& to) override {
    const auto failed = [&](const std::string& why) {
      throw FileSystemError(to.string() + ": cannot copy " + from.string() + ": " + why);
    };
    // Without blocking, as every read of a file: opening a named pipe would wait for a writer.
    const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (in < 0) failed(std::strerror(errno));
    struct stat st {};
    if (::fstat(in, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(in);
      failed("not a regular file");
    }
    ::fcntl(in, F_SETFL, ::fcntl(in, F_GETFL) & ~O_NONBLOCK);
    return copy_and_hash(in, from, to);
  }

  bool rename(const fs::path& from, const fs::path& to) override {
    if (::rename(from.c_str(), to.c_str()) == 0) return true;
    const int error = errno;
    if (error == ENOTEMPTY || error == EEXIST || error == EISDIR) return false;
    if (error == EXDEV)
      throw CrossDevice(to.string() + ": cannot move " + from.string() + " here: " + std::strerror(error));
    fail(to, "cannot move " + from.string() + " here", error);
  }

  fs::path real_path(const fs::path& path) const override {
    std::error_code ec;
    const fs::path real = fs::weakly_canonical(path, ec);
    return ec ? path : real;
  }

  // Walked with the types the folder listing gives (d_type): no stat per entry where the file system
  // tells them (a stat where it does not). Committing an artifact walks its folder.
  std::vector<std::string> files_below(const fs::path& folder) const override {
    std::vector<std::string> files;
    const std::string& root = folder.native();
    const size_t prefix = root.size() + (!root.empty() && root.back() == '/' ? 0 : 1);
    std::error_code ec;
    for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
      if (!it->is_symlink(ec) && it->is_regular_file(ec)) files.push_back(it->path().generic_string().substr(prefix));
    std::sort(files.begin(), files.end());
    return files;
  }

  std::vector<std::string> list(const fs::path& folder) const override {
    std::vector<std::string> names;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
      names.push_back(it->path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  FileStat stat(const fs::path& path, bool follow_link) const override {
    struct stat st {};
    if ((follow_link ? ::stat(path.c_str(), &st) : ::lstat(path.c_str(), &st)) != 0) return {};
    return {type_of(st.st_mode), static_cast<uint64_t>(st.st_size),
            static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec,
            static_cast<uint64_t>(st.st_ino)};
  }

  void make_folders(const fs::path& folder) override {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) throw FileSystemError(folder.string() + ": cannot create folder: " + ec.message());
  }

  void remove(const fs::path& path) override {
    // remove_all does not follow symbolic links: a link is removed, not what it points to.
    std::error_code ec;
    fs::remove_all(path, ec);
  }

  void sync(const fs::path& path) override { sync_file_system(path); }

  std::unique_ptr<Lock> lock(const fs::path& file, bool shared, const std::function<void()>& on_wait) override {
    return std::make_unique<FlockLock>(file, shared, on_wait);
  }
};

}  // namespace

bool orphaned_temp(const std::string& name) {
  if (name.rfind(".tmp.", 0) != 0) return false;
  // .tmp.<name>.<host>.<pid>.<n>: the pid is the second field from the end, the host the third.
  const auto last = name.rfind('.');
  const auto before = last == std::string::npos || last == 0 ? std::string::npos : name.rfind('.', last - 1);
  if (before == std::string::npos || before == 0) return false;
  const auto host_at = name.rfind('.', before - 1);
  if (host_at == std::string::npos || name.compare(host_at + 1, before - host_at - 1, host_name()) != 0)
    return false;  // another machine's (or an older OLT's): its pid cannot be judged here
  const std::string pid = name.substr(before + 1, last - before - 1);
  if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) return false;
  return ::kill(static_cast<pid_t>(std::stol(pid)), 0) != 0 && errno == ESRCH;  // not alive, and ours to judge
}

FileSystem& real_file_system() {
  static RealFileSystem real;
  return real;
}

void write_pieces(FileSystem& files, const fs::path& file, const std::function<void(const PieceSink&)>& make) {
  bool written = false;
  make([&](std::string_view piece) {
    if (written) {
      files.append(file, piece);
    } else {
      files.write(file, piece);
      written = true;
    }
  });
  if (!written) files.write(file, "");
}

size_t remove_orphaned_temps(FileSystem& files, const fs::path& dir) {
  size_t removed = 0;
  for (const auto& name : files.list(dir)) {
    const fs::path path = dir / name;
    if (orphaned_temp(name)) {
      files.remove(path);
      ++removed;
    } else if (files.stat(path).is_folder()) {
      removed += remove_orphaned_temps(files, path);
    }
  }
  return removed;
}

}  // namespace olt
