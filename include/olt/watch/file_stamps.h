#pragma once
// What `olt watch` compares to notice an edit: each watched file's identity (inode), size and
// modification time, read with one stat() each. Polling stamps works the same on network file
// systems (NFS, SMB), where annotators often keep their boxes and inotify (olt/watch/change_events.h)
// sees nothing, and sees the rename-into-place saves of editors as an inode change.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace olt {

struct FileStamp {
  bool exists = false;
  std::uintmax_t size = 0;
  std::int64_t mtime_ns = 0;
  std::uint64_t inode = 0;
  bool operator==(const FileStamp& o) const {
    return exists == o.exists && size == o.size && mtime_ns == o.mtime_ns && inode == o.inode;
  }
  bool operator!=(const FileStamp& o) const { return !(*this == o); }
};

using FileStamps = std::map<std::filesystem::path, FileStamp>;

/// The stamp of every file in `files` (a missing file has exists = false).
FileStamps stamp_files(const std::vector<std::filesystem::path>& files);

/// Files whose stamp differs between `before` and `after`, or that only one of them lists.
std::vector<std::filesystem::path> changed_files(const FileStamps& before, const FileStamps& after);

}  // namespace olt
