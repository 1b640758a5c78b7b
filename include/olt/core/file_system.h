#pragma once
// The file operations of the cache, the input digests, the artifact folders and publishing, behind
// one small interface: the real file system for runs, a memory one for tests (tests/support: fast,
// and able to fail on cue, as a disk that fills up at the N-th write).
// Nothing here follows a symbolic link when it removes or describes a path: `stat` describes the
// link itself and `remove` removes the link, never what it points to.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "olt/core/fs.h"
#include "olt/core/pieces.h"

namespace olt {

struct FileStat {
  enum class Type { missing, file, folder, link, other };
  Type type = Type::missing;
  uint64_t size = 0;      ///< bytes, for files
  int64_t mtime_ns = 0;   ///< last modification
  uint64_t identity = 0;  ///< inode (equal for hard links of one file)

  bool exists() const { return type != Type::missing; }
  bool is_file() const { return type == Type::file; }
  bool is_folder() const { return type == Type::folder; }
  /// Whether `other` is this same file, unchanged: a file of the same inode, size and time. Files
  /// OLT writes once and renames into place are another file when replaced. A stat without an
  /// inode (0) is never the same.
  bool same_file(const FileStat& other) const {
    return is_file() && other.is_file() && identity != 0 && identity == other.identity && size == other.size &&
           mtime_ns == other.mtime_ns;
  }
};

/// A write that failed for lack of space or another system reason: the message names the file and
/// says why ("No space left on device").
class FileSystemError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A rename between two file systems (`to` lies below a mount point `from` does not): nothing moved.
class CrossDevice : public FileSystemError {
 public:
  using FileSystemError::FileSystemError;
};

/// A sync that failed (a write-back error): what was written since the last one may not be on the
/// disk, though reads may still return the new bytes from memory while the disk holds others.
class SyncFailed : public FileSystemError {
 public:
  using FileSystemError::FileSystemError;
};

/// Tells whether anything changed in some folders since it began: a file or folder in one of them
/// made, removed, renamed, written or given other attributes, or one of the folders itself moved or
/// removed. Any doubt is a change.
class FolderWatch {
 public:
  virtual ~FolderWatch() = default;
  /// Whether anything changed since the watch began or last began again (once true, it stays so).
  virtual bool changed() = 0;
  /// Begins again from now, over these folders too: what changed so far is forgotten (a publish's
  /// own changes). False when it cannot tell what it watches any more (one of its folders removed or
  /// moved, events lost, a folder that cannot be watched): the watch is then of no use. It follows the
  /// folders it began on, not their paths: one put in another's place (an ancestor moved) is not told.
  virtual bool restart(const std::vector<fs::path>& folders) = 0;
};

class FileSystem {
 public:
  virtual ~FileSystem() = default;
  /// A whole regular file; throws InputError naming it when missing, a folder or too large.
  virtual std::string read(const fs::path& file) const = 0;
  /// A regular file's bytes as a stream (see open_file_stream; read whole where the file system
  /// cannot stream); errors as `read`.
  virtual std::unique_ptr<std::istream> read_stream(const fs::path& file) const;
  /// SHA-256 of a regular file, hex (streamed where the file system can).
  virtual std::string sha256(const fs::path& file) const;
  /// Writes `bytes` to `file` in place (parent folders created); throws FileSystemError.
  virtual void write(const fs::path& file, std::string_view bytes) = 0;
  /// Appends `bytes` in one write (concurrent appenders do not interleave short lines).
  virtual void append(const fs::path& file, std::string_view bytes) = 0;
  /// `to` becomes the same file as `from` (a hard link; a copy where there is none).
  virtual void link(const fs::path& from, const fs::path& to) = 0;
  /// `to` becomes a copy of `from`'s bytes (parent folders created).
  virtual void copy(const fs::path& from, const fs::path& to) = 0;
  /// What copy_hashed did: the SHA-256 (hex) of the bytes copied, and whether `to` is a clone of
  /// `from` (it shares its blocks until either is written).
  struct Copied {
    std::string sha256;
    bool cloned = false;
  };
  /// As copy, and the SHA-256 (hex) of the bytes copied: read once where the file system can (the
  /// real one hashes them on the way; any other copies, then hashes `to`). The real one makes `to` a
  /// clone of `from` where their file system can (XFS with reflink, Btrfs), and hashes `from`.
  virtual Copied copy_hashed(const fs::path& from, const fs::path& to);
  /// Moves atomically; replaces a file at `to`. Returns false (nothing moved) when `to` is a folder
  /// that exists; throws CrossDevice where `to` is on another file system, FileSystemError on other
  /// failures.
  virtual bool rename(const fs::path& from, const fs::path& to) = 0;
  /// `path` with every symbolic link on the way resolved (the parts that do not exist kept as given).
  virtual fs::path real_path(const fs::path& path) const = 0;
  /// Names in a folder, sorted; empty when it is missing or not a folder.
  virtual std::vector<std::string> list(const fs::path& folder) const = 0;
  /// What is at `path`: a final symbolic link itself, or with `follow_link` what it points to.
  virtual FileStat stat(const fs::path& path, bool follow_link = false) const = 0;
  virtual void make_folders(const fs::path& folder) = 0;
  /// Removes a file, a link (not what it points to) or a folder with everything below it, never
  /// following links; nothing to remove is not an error.
  virtual void remove(const fs::path& path) = 0;
  /// Makes everything written so far on the file systems holding `paths` durable, each file system
  /// once (a sync waits for every byte not yet on its disk, anyone's). Throws SyncFailed where the
  /// file system says it failed (not where a path cannot be opened: FileSystemError).
  virtual void sync(const std::vector<fs::path>& paths) = 0;
  /// Held while it lives; let go on any thread (a run's stages share one: runtime/stage_locks.h).
  class Lock {
   public:
    virtual ~Lock() = default;
  };
  /// Blocks until the lock named by `file` is held: exclusively, or `shared` with other shared
  /// holders. `on_wait` is called once, before blocking, when another holder has it. With `stop`,
  /// the wait ends once it is set: null then (retry_until_stopped). On the real file system:
  /// flock(2), shared by every process and released by the kernel when its holder dies (see
  /// olt/cache/lock.h).
  virtual std::unique_ptr<Lock> lock(const fs::path& file, bool shared, const std::function<void()>& on_wait,
                                     const std::atomic<bool>* stop) = 0;
  /// The same lock if no other holder has it now; null when one has (never waits).
  virtual std::unique_ptr<Lock> try_lock(const fs::path& file, bool shared) = 0;
  /// Writes `bytes` to `file` so that readers see the old file or the new one, never a part (the
  /// real one syncs the bytes before the rename, so a power loss leaves one of the two as well).
  virtual void write_atomic(const fs::path& file, std::string_view bytes);
  /// A watch over `folders` (what is directly in each; on the real file system, inotify); null where
  /// this file system cannot tell (the default), or one of them cannot be watched.
  virtual std::unique_ptr<FolderWatch> watch(const std::vector<fs::path>& folders);
  /// Every regular file below `folder`, as '/'-separated paths relative to it, sorted; links and
  /// what they point to are not included.
  virtual std::vector<std::string> files_below(const fs::path& folder) const;
};

/// The machine's file system.
FileSystem& real_file_system();

/// Calls `take` until it says it took what it waits for (true), or `stop` is set first (false): after
/// 1 ms, then twice as long each time up to 250 ms. For a wait that a signal handler's flag must end
/// (flock(2) cannot wait for one): it ends at most 250 ms after either.
bool retry_until_stopped(const std::function<bool()>& take, const std::atomic<bool>& stop);

/// Makes `file` anew in one step: `make` writes a temporary sibling (see temp_sibling), which is
/// then renamed over `file`. Returns false when `file` is a folder; the sibling is removed then and
/// on any failure (which is thrown on).
bool replace_with(FileSystem& files, const fs::path& file, const std::function<void(const fs::path& temp)>& make);

/// Writes `bytes` as `file` in one step (replace_with), not synced: readers see the old file or the
/// new one, and a power loss before its file system's next sync can leave it empty. Throws
/// FileSystemError where `file` is a folder.
void replace_unsynced(FileSystem& files, const fs::path& file, std::string_view bytes);

/// Writes `file` with the text `make` hands to its sink in pieces (olt/core/pieces.h): the first
/// written, the others appended; an empty file when it hands none.
void write_pieces(FileSystem& files, const fs::path& file, const std::function<void(const PieceSink&)>& make);

/// Removes, below `dir`, the temporary siblings (see temp_sibling) left by processes that died
/// before their rename (their pid is no longer running); those of live processes stay. Never follows
/// a symbolic link. Returns how many it removed.
size_t remove_orphaned_temps(FileSystem& files, const fs::path& dir);

/// Whether `name` is a temporary sibling (.tmp.<name>.<host>.<pid>.<n>) of a process of this
/// machine that is no longer running.
bool orphaned_temp(const std::string& name);

}  // namespace olt
