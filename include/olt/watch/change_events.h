#pragma once
// What the system says of changes to the files `olt watch` watches (Linux inotify on their folders),
// alongside polling their stamps (olt/watch/file_stamps.h): a change is noticed when it happens
// rather than at the next poll, and a write known to be finished (the file closed after writing,
// renamed into place) need not wait out the settle time. Where the system says nothing (network
// file systems: NFS, SMB; inotify unavailable or its limits reached), polling alone sees the changes,
// as before.
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <map>
#include <set>
#include <vector>

namespace olt {

/// What happened to one of the watched files, as far as the system said.
enum class ChangeEvent {
  none,      ///< nothing within the time waited
  changed,   ///< written, created, removed or moved away: perhaps not finished
  finished,  ///< closed after writing, renamed into place, or its attributes changed
};

class ChangeEvents {
 public:
  /// Listens for changes to `files` (their folders, filtered by name); inactive where the system
  /// cannot tell.
  explicit ChangeEvents(const std::vector<std::filesystem::path>& files);
  ~ChangeEvents();
  ChangeEvents(const ChangeEvents&) = delete;
  ChangeEvents& operator=(const ChangeEvents&) = delete;

  /// The most folders listened to: more are left to polling.
  static constexpr size_t kMaxFolders = 64;

  /// Whether the system reports changes here (else wait() only sleeps).
  bool active() const { return fd_ >= 0; }
  /// The folders listened to.
  size_t folders() const { return folders_.size(); }
  /// Waits up to `seconds`, or until `stop`, for an event about a watched file, and returns as soon
  /// as one comes: the last of the events read then. Events about other files in the same folders
  /// are read and left out.
  ChangeEvent wait(double seconds, const std::atomic<bool>& stop);

 private:
  ChangeEvent read_events();

  int fd_ = -1;
  std::map<int, std::filesystem::path> folders_;  ///< by watch descriptor
  std::set<std::filesystem::path> files_;
};

}  // namespace olt
