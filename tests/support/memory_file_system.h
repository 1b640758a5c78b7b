#pragma once
// A file system in memory, for tests: fast, and able to fail on cue. It keeps the real one's
// semantics where the cache and publishing depend on them: hard links share bytes (a write through
// one changes all), a symbolic link in the middle of a path is followed (as the kernel does for open
// and unlink), a final one only by read, write and list. No working folder: use absolute paths.
#include <memory>

#include "olt/core/file_system.h"
#include "support/temp_dir.h"

namespace olt::test {

/// Thread-safe. `fail_writes_after(n)`: the n+1-th write,
/// append, link or copy from now on (and every later one) fails as a full disk does.
class MemoryFileSystem : public FileSystem {
 public:
  MemoryFileSystem();
  ~MemoryFileSystem() override;
  std::string read(const fs::path& file) const override;
  void write(const fs::path& file, std::string_view bytes) override;
  void append(const fs::path& file, std::string_view bytes) override;
  void link(const fs::path& from, const fs::path& to) override;
  void copy(const fs::path& from, const fs::path& to) override;
  /// As copy; a clone where clone_copies was called and both are on one file system.
  Copied copy_hashed(const fs::path& from, const fs::path& to) override;
  bool rename(const fs::path& from, const fs::path& to) override;
  fs::path real_path(const fs::path& path) const override;
  std::vector<std::string> list(const fs::path& folder) const override;
  FileStat stat(const fs::path& path, bool follow_link = false) const override;
  void make_folders(const fs::path& folder) override;
  void remove(const fs::path& path) override;
  /// Everything written on the file systems holding `paths` (the root's, or a mount's) survives a
  /// power loss from now on. Counts one sync per file system.
  void sync(const std::vector<fs::path>& paths) override;
  /// As the real one: the bytes are synced before the rename.
  void write_atomic(const fs::path& file, std::string_view bytes) override;
  /// An in-process reader-writer lock per path.
  std::unique_ptr<Lock> lock(const fs::path& file, bool shared, const std::function<void()>& on_wait,
                             const std::atomic<bool>* stop) override;
  std::unique_ptr<Lock> try_lock(const fs::path& file, bool shared) override;
  /// Sees every change made through this file system to what is directly in the folders, or to
  /// the folders themselves.
  std::unique_ptr<FolderWatch> watch(const std::vector<fs::path>& folders) override;

  /// A symbolic link at `link` to `target` (as `ln -s`), for tests of what must not follow it.
  void symlink(const fs::path& target, const fs::path& link);
  /// `folder` becomes a mount point: a rename into or out of it throws CrossDevice, as the kernel's
  /// fails with EXDEV.
  void mount(const fs::path& folder);
  /// From now on a copy_hashed within one file system says it cloned, as on XFS or Btrfs (the bytes
  /// are copied all the same).
  void clone_copies();
  /// How many of those clones were made of a file with bytes not yet synced (which XFS writes to
  /// the disk first, one file at a time).
  int64_t clones_of_unsynced() const;
  void fail_writes_after(int64_t writes);
  /// The power goes at the n+1-th write from now on (n = `writes`), as lose_power.
  void cut_power_after(int64_t writes);
  /// The power goes now, as a journaling file system in ordered mode (ext4's default) leaves it:
  /// every change to names and folders made so far stays; each file's bytes written since its file
  /// system was last synced (sync; write_atomic syncs its own) are written back in part: the file
  /// is cut in the middle of them (a file written anew keeps half its bytes, one appended to half
  /// of what was appended). Every change after this throws until restore_power.
  void lose_power();
  void restore_power();
  /// The n+1-th call of sync from now on (n = `syncs`) throws SyncFailed (EIO), as a disk that
  /// failed to write some bytes back; the others succeed.
  void fail_sync_after(int64_t syncs);
  /// A lock file's lock (lock, try_lock), let go on any thread, as flock is.
  struct FileLock;

  /// How many writes, appends, links and copies succeeded so far.
  int64_t writes() const;
  /// How many file systems were synced, summed over the calls to sync.
  int64_t syncs() const;

 private:
  std::shared_ptr<FileLock> file_lock(const fs::path& file);
  struct State;
  class Watch;
  std::shared_ptr<State> state_;  ///< shared with its watches, which may outlive it
};

/// A folder on the real file system (a temporary one) or on a memory one, for tests that must give
/// the same answers on both: `Place place(GENERATE(true, false))`.
class Place {
 public:
  explicit Place(bool real) : root_(real ? temp_.path() : fs::path("/place")) {
    if (real) files_ = &real_file_system();
  }
  FileSystem& files() { return *files_; }
  const fs::path& root() const { return root_; }
  bool real() const { return files_ != &memory_; }
  /// A symbolic link at `link` to `target`, on either.
  void symlink(const fs::path& target, const fs::path& link);

 private:
  TempDir temp_;
  MemoryFileSystem memory_;
  FileSystem* files_ = &memory_;
  fs::path root_;
};

}  // namespace olt::test
