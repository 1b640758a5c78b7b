#pragma once
// What the system says of changes to the files `olt watch` watches (Linux inotify on their folders),
// alongside polling their stamps (olt/watch/file_stamps.h): a save is noticed when its writer
// finishes it (closes the file after writing, renames it into place) rather than at the next poll,
// and need not wait out the settle time. Where the system says nothing (network file systems: NFS,
// SMB; inotify unavailable or its limits reached; folders beyond those listened to), polling alone
// sees the changes, as before.
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace olt {

class ChangeEvents {
 public:
  /// The most folders, and the most watched files in them, listened to: the folders holding the
  /// fewest watched files first (the job's, the boxes'); the others are left to polling.
  static constexpr size_t kMaxFolders = 64;
  static constexpr size_t kMaxFiles = 4096;

  /// Listens for changes to `files`; `enabled` false (or a system that cannot tell) listens to none.
  explicit ChangeEvents(const std::vector<std::filesystem::path>& files, bool enabled = true);
  ~ChangeEvents();
  ChangeEvents(const ChangeEvents&) = delete;
  ChangeEvents& operator=(const ChangeEvents&) = delete;

  /// The folders listened to (none where the system reports nothing).
  size_t folders() const { return folders_.size(); }

  /// Waits up to `seconds`, or until `stop`; returns early, true, when the system reports a watched
  /// file finished (closed after writing, or renamed into place).
  /// Other events are noted, not waited for: a file being written wakes no one until it is finished.
  bool wait(double seconds, const std::atomic<bool>& stop);
  /// Whether every file of `changed` was reported finished by its last event (and nothing since was
  /// lost to a full event queue): false for a file the system said nothing of.
  bool finished(const std::vector<std::filesystem::path>& changed) const;

 private:
  bool read_events();

  int fd_ = -1;
  std::map<int, std::vector<std::filesystem::path>> folders_;  ///< by watch descriptor: its spellings
  std::set<std::filesystem::path> files_;                      ///< the watched files in those folders
  std::map<std::filesystem::path, bool> last_;  ///< per file reported: whether its last event finished it
  bool lost_ = false;                           ///< events were lost (a full queue, a folder gone)
};

}  // namespace olt
