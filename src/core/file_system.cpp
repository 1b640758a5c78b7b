// The machine's file system behind FileSystem, and what every file system shares.
#include "olt/core/file_system.h"

#include <fcntl.h>
#include <linux/fs.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <functional>
#include <mutex>
#include <sstream>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "folder_watch.h"
#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/fs.h"
#include "olt/core/hash.h"

namespace olt {

std::string FileSystem::sha256(const fs::path& file) const { return sha256_hex(read(file)); }

FileSystem::Copied FileSystem::copy_hashed(const fs::path& from, const fs::path& to) {
  copy(from, to);
  return {sha256(to), false};
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

void replace_unsynced(FileSystem& files, const fs::path& file, std::string_view bytes) {
  if (!replace_with(files, file, [&](const fs::path& temp) { files.write(temp, bytes); }))
    throw FileSystemError(file.string() + ": cannot replace: it is a folder");
}

void FileSystem::write_atomic(const fs::path& file, std::string_view bytes) { replace_unsynced(*this, file, bytes); }

std::unique_ptr<std::istream> FileSystem::read_stream(const fs::path& file) const {
  return std::make_unique<std::istringstream>(read(file));
}

std::unique_ptr<FolderWatch> FileSystem::watch(const std::vector<fs::path>&) { return nullptr; }

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

// A file descriptor, closed when it goes.
struct OpenFile {
  int fd = -1;
  OpenFile() = default;
  OpenFile(const OpenFile&) = delete;
  OpenFile& operator=(const OpenFile&) = delete;
  ~OpenFile() {
    if (fd >= 0) ::close(fd);
  }
};

// What is left to read of `fd`, hashed: its SHA-256 (hex) and size. Each piece read is also handed
// to `also` where given (a copy's write). Read errors are FileSystemError naming `to`.
struct Hashed {
  std::string sha256;
  uint64_t bytes = 0;
};
Hashed hash_rest(int fd, const fs::path& to, const std::string& what,
                 const std::function<void(std::string_view)>& also = nullptr) {
  Sha256 hash;
  uint64_t bytes = 0;
  std::array<char, 1 << 16> buffer;  // NOLINT(cppcoreguidelines-pro-type-member-init): filled by read
  for (;;) {
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(to, what, errno);
    if (n == 0) return {hash.hex(), bytes};
    const std::string_view piece(buffer.data(), static_cast<size_t>(n));
    hash.update(piece);
    bytes += piece.size();
    if (also) also(piece);
  }
}

// The pairs of file systems (from, to) where a clone was refused as not supported (tmpfs, ext4:
// EOPNOTSUPP), not asked again: a publish of 1,900 files on tmpfs asked 1,900 times. A refusal for
// two mounts (EXDEV) is asked again: before Linux 5.18 two mounts of one file system refuse it too,
// and share its device number. Made once and never destroyed (a copy may run while the process
// exits). A device number a file system left and another took (an unmount and a mount while the
// daemon runs) is copied rather than cloned: the same bytes either way.
struct RefusedClones {
  std::mutex mutex;
  std::vector<std::pair<dev_t, dev_t>> between;
};
RefusedClones& refused_clones() {
  static auto* refused = new RefusedClones;  // NOLINT(cppcoreguidelines-owning-memory): see above
  return *refused;
}

bool clone_refused(RefusedClones& refused, const std::pair<dev_t, dev_t>& between) {
  return std::find(refused.between.begin(), refused.between.end(), between) != refused.between.end();
}

// `out` (empty) made a clone of `in` where the file system can (XFS with reflink, Btrfs: FICLONE): it
// shares `in`'s blocks until either is written. False where it cannot (ext4, tmpfs: EOPNOTSUPP)
// or the two are on two file systems or mounts (EXDEV), which leave `out` as it was; a clone that
// failed on the way may have left a part, cut off again. `in_st` and `out_st`: the two files' stats.
bool cloned(int in, int out, const struct stat& in_st, const struct stat& out_st, const fs::path& to,
            const std::string& what) {
  RefusedClones& refused = refused_clones();
  const std::pair<dev_t, dev_t> between(in_st.st_dev, out_st.st_dev);
  {
    const std::lock_guard<std::mutex> lock(refused.mutex);
    if (clone_refused(refused, between)) return false;
  }
  if (::ioctl(out, FICLONE, in) == 0) return true;
  if (errno == EOPNOTSUPP) {
    const std::lock_guard<std::mutex> lock(refused.mutex);
    if (!clone_refused(refused, between)) refused.between.push_back(between);
    return false;
  }
  if (errno != EXDEV && ::ftruncate(out, 0) != 0) fail(to, what, errno);
  return false;
}

void close_written(OpenFile& out, const fs::path& to, const std::string& what) {
  const int closed = ::close(out.fd);
  out.fd = -1;
  if (closed != 0) fail(to, what, errno);
}

// Copies regular file `from` to `to` (made, or cut to nothing, with its folders where missing),
// hashing the bytes on the way. Both are opened without blocking and checked: a named pipe on either
// side is refused, not waited on, and `to` being `from` (or a link to it) is refused, not emptied
// before it is read. Failures are FileSystemError naming both (the cache's files, not the user's
// input).
// Where the file system can, `to` is a clone (cloned above): publishing then writes no file's bytes a
// second time, and the output takes no room of its own. `from` is read for the hash then, and `to`'s
// size checked against it: the clone holds the blocks `from` holds.
FileSystem::Copied copy_and_hash(const fs::path& from, const fs::path& to) {
  const std::string what = "cannot copy " + from.string();
  OpenFile in, out;
  try {
    uint64_t size = 0;
    in.fd = open_regular_file(from, &size);
  } catch (const InputError& e) {
    throw FileSystemError(to.string() + ": " + what + ": " +
                          (e.diagnostics().empty() ? e.what() : e.diagnostics().front().message));
  }
  out.fd =
      open_creating_folders(to, [&] { return ::open(to.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | O_NONBLOCK, 0644); });
  if (out.fd < 0) fail(to, what, errno);
  struct stat in_st {};
  struct stat out_st {};
  if (::fstat(in.fd, &in_st) != 0 || ::fstat(out.fd, &out_st) != 0 || !S_ISREG(out_st.st_mode))
    throw FileSystemError(to.string() + ": " + what + ": the target is not a regular file");
  if (in_st.st_dev == out_st.st_dev && in_st.st_ino == out_st.st_ino)
    throw FileSystemError(to.string() + ": " + what + ": they are the same file");
  // Cut to nothing for the clone too: one over a longer file would leave the rest of it (a file
  // just made, as publishing's are, is empty already).
  if (out_st.st_size != 0 && ::ftruncate(out.fd, 0) != 0) fail(to, what, errno);
  ::fcntl(out.fd, F_SETFL, 0);  // blocking again (its one status flag was O_NONBLOCK): one call
  if (cloned(in.fd, out.fd, in_st, out_st, to, what)) {
    const Hashed read = hash_rest(in.fd, to, what);
    if (::fstat(out.fd, &out_st) != 0 || static_cast<uint64_t>(out_st.st_size) != read.bytes)
      throw FileSystemError(to.string() + ": " + what + ": the clone is not the size of what it was made from");
    close_written(out, to, what);
    return {read.sha256, true};
  }
  const Hashed copied = hash_rest(in.fd, to, what, [&](std::string_view piece) {
    if (const int error = write_fully(out.fd, piece)) fail(to, what, error);
  });
  close_written(out, to, what);
  return {copied.sha256, false};
}

FileStat::Type type_of(mode_t mode) {
  if (S_ISREG(mode)) return FileStat::Type::file;
  if (S_ISDIR(mode)) return FileStat::Type::folder;
  if (S_ISLNK(mode)) return FileStat::Type::link;
  return FileStat::Type::other;
}

// A lock file opened: the lock is held once hold() or try_hold() says so, until it is destroyed.
class FlockLock : public FileSystem::Lock {
 public:
  FlockLock(const fs::path& file, bool shared) : file_(file), mode_(shared ? LOCK_SH : LOCK_EX) {
    if (file.has_parent_path()) real_file_system().make_folders(file.parent_path());
    fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) fail(file, "cannot open lock file", errno);
  }
  ~FlockLock() override { ::close(fd_); }  // closing releases the lock
  FlockLock(const FlockLock&) = delete;
  FlockLock& operator=(const FlockLock&) = delete;

  /// Whether it is held now: false when another holder has it.
  bool try_hold() {
    if (::flock(fd_, mode_ | LOCK_NB) == 0) return true;
    if (errno != EWOULDBLOCK && errno != EINTR) fail(file_, "cannot lock", errno);
    return false;  // held by another, or cut short by a signal: a waiting caller tries again
  }
  void hold() {
    while (::flock(fd_, mode_) != 0)
      if (errno != EINTR) fail(file_, "cannot lock", errno);
  }

 private:
  fs::path file_;
  int mode_;
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
    std::error_code missing;
    if (!copy_file() && (ec == std::errc::no_such_file_or_directory || ec == std::errc::not_a_directory) &&
        to.has_parent_path() && fs::exists(from, missing)) {
      make_folders(to.parent_path());  // tried first: a folder already there costs no stat
      copy_file();
    }
    if (ec) throw FileSystemError(to.string() + ": cannot copy " + from.string() + ": " + ec.message());
  }

  Copied copy_hashed(const fs::path& from, const fs::path& to) override {
    if (const int error = injected_write_error()) fail(to, "cannot copy " + from.string(), error);
    return copy_and_hash(from, to);
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
    // A folder that cannot be read (or a file gone on the way): walked as every file system is,
    // each folder on its own, so that one such folder loses only its own files.
    if (ec) return FileSystem::files_below(folder);
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

  void sync(const std::vector<fs::path>& paths) override {
    try {
      sync_file_systems(paths);
    } catch (const std::system_error& e) {
      throw SyncFailed(e.what());
    }
  }

  std::unique_ptr<Lock> lock(const fs::path& file, bool shared, const std::function<void()>& on_wait,
                             const std::atomic<bool>* stop) override {
    auto lock = std::make_unique<FlockLock>(file, shared);
    if (lock->try_hold()) return lock;
    if (on_wait) on_wait();
    if (!stop) {
      lock->hold();
      return lock;
    }
    // Tried again on the one open file: a lock request each time, no open (on NFS, a round trip).
    return retry_until_stopped([&] { return lock->try_hold(); }, *stop) ? std::move(lock) : nullptr;
  }
  std::unique_ptr<Lock> try_lock(const fs::path& file, bool shared) override {
    auto lock = std::make_unique<FlockLock>(file, shared);
    return lock->try_hold() ? std::move(lock) : nullptr;
  }
  std::unique_ptr<FolderWatch> watch(const std::vector<fs::path>& folders) override {
    return watch_real_folders(folders);
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

bool retry_until_stopped(const std::function<bool()>& take, const std::atomic<bool>& stop) {
  for (std::chrono::milliseconds pause{1};; pause = std::min(2 * pause, std::chrono::milliseconds{250})) {
    if (stop) return false;
    std::this_thread::sleep_for(pause);
    if (take()) return true;
  }
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
