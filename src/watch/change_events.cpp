#include "olt/watch/change_events.h"

#include <poll.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <utility>

namespace olt {
namespace {

using Clock = std::chrono::steady_clock;

// A file's writer finished it; a file changed (perhaps still being written: also a new modification
// time set, as `touch` does); a folder's watch ended.
constexpr uint32_t kFinishing = IN_CLOSE_WRITE | IN_MOVED_TO;
constexpr uint32_t kChanging = IN_MODIFY | IN_CREATE | IN_DELETE | IN_MOVED_FROM;
constexpr uint32_t kFolderGone = IN_DELETE_SELF | IN_MOVE_SELF | IN_IGNORED;

}  // namespace

ChangeEvents::ChangeEvents(const std::vector<std::filesystem::path>& files, bool enabled) {
  if (!enabled) return;
  // The folders holding the fewest watched files first, up to the limits: a recording's image
  // folders (or a folder per frame) do not take the inotify watches the user's editors share.
  std::map<std::filesystem::path, size_t> count;
  for (const auto& file : files) ++count[file.parent_path()];
  std::vector<std::pair<size_t, std::filesystem::path>> by_count;
  for (const auto& [folder, n] : count) by_count.emplace_back(n, folder);
  std::sort(by_count.begin(), by_count.end());
  std::set<std::filesystem::path> chosen;
  size_t chosen_files = 0;
  for (const auto& [n, folder] : by_count) {
    if (chosen.size() == kMaxFolders || chosen_files + n > kMaxFiles) break;
    chosen.insert(folder);
    chosen_files += n;
  }
  if (chosen.empty() || (fd_ = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) < 0) return;
  std::set<std::filesystem::path> listened;
  for (const auto& folder : chosen) {
    // A folder that is not there (yet) is left to polling, as is one beyond the system's limit. Two
    // spellings of one folder share its watch.
    const int wd = ::inotify_add_watch(fd_, folder.c_str(), kFinishing | kChanging | kFolderGone | IN_ONLYDIR);
    if (wd < 0) continue;
    folders_[wd].push_back(folder);
    listened.insert(folder);
  }
  for (const auto& file : files)
    if (listened.count(file.parent_path())) files_.insert(file);
  if (folders_.empty()) {
    ::close(fd_);
    fd_ = -1;
  }
}

ChangeEvents::~ChangeEvents() {
  if (fd_ >= 0) ::close(fd_);
}

bool ChangeEvents::read_events() {
  // Room for many events at once: each is a header and a name of at most NAME_MAX + 1 bytes.
  alignas(inotify_event) char buffer[64 * 1024];
  bool any_finished = false;
  for (;;) {
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n <= 0) return any_finished;  // none left (EAGAIN), or an error: polling still sees the change
    for (ssize_t at = 0; at < n;) {
      const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
      at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
      if (event->mask & IN_Q_OVERFLOW) {  // events lost: what they said is not known
        lost_ = true;
        continue;
      }
      const auto folder = folders_.find(event->wd);
      if (folder == folders_.end()) continue;
      if (event->mask & kFolderGone) {  // removed or moved away: its files are polling's from here
        lost_ = true;
        if (!(event->mask & IN_IGNORED)) ::inotify_rm_watch(fd_, event->wd);
        folders_.erase(folder);
        continue;
      }
      if (event->len == 0) continue;
      for (const auto& spelling : folder->second) {
        const std::filesystem::path file = spelling / event->name;
        if (!files_.count(file)) continue;
        const bool finishing = event->mask & kFinishing;
        last_[file] = finishing;
        any_finished = any_finished || finishing;
      }
    }
  }
}

bool ChangeEvents::wait(double seconds, const std::atomic<bool>& stop) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    if (stop) return false;
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(until - Clock::now()).count();
    // In slices of at most 20 ms, so that a stop is seen soon; the events queued are read even when
    // no time is left.
    const int slice = static_cast<int>(std::clamp<long long>(left, 0, 20));
    if (fd_ < 0) {
      if (left <= 0) return false;
      ::poll(nullptr, 0, slice);
      continue;
    }
    pollfd readable{fd_, POLLIN, 0};
    if (::poll(&readable, 1, slice) > 0 && read_events()) return true;
    if (left <= 0) return false;
  }
}

bool ChangeEvents::finished(const std::vector<std::filesystem::path>& changed) const {
  if (lost_ || changed.empty()) return false;
  return std::all_of(changed.begin(), changed.end(), [&](const std::filesystem::path& file) {
    const auto it = last_.find(file);
    return it != last_.end() && it->second;
  });
}

}  // namespace olt
