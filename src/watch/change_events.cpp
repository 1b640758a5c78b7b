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

// The events that say a file was finished, and the others that say it changed.
constexpr uint32_t kFinished = IN_CLOSE_WRITE | IN_MOVED_TO | IN_ATTRIB;
constexpr uint32_t kChanged = IN_MODIFY | IN_CREATE | IN_DELETE | IN_MOVED_FROM;

}  // namespace

ChangeEvents::ChangeEvents(const std::vector<std::filesystem::path>& files) : files_(files.begin(), files.end()) {
  fd_ = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd_ < 0) return;
  // The folders holding the fewest watched files first (the job's, the boxes'), up to kMaxFolders:
  // a recording that keeps each frame in a folder of its own does not take the user's inotify
  // watches (shared with editors and IDEs); its images are left to polling.
  std::map<std::filesystem::path, size_t> count;
  for (const auto& file : files_) ++count[file.parent_path()];
  std::vector<std::pair<size_t, std::filesystem::path>> folders;
  for (const auto& [folder, n] : count) folders.emplace_back(n, folder);
  std::sort(folders.begin(), folders.end());
  for (const auto& [n, folder] : folders) {
    if (folders_.size() == kMaxFolders) break;
    // A folder that is not there (yet) is left to polling, as is one beyond the system's limit.
    const int wd = ::inotify_add_watch(fd_, folder.c_str(), kFinished | kChanged | IN_ONLYDIR);
    if (wd >= 0) folders_[wd] = folder;
  }
  if (folders_.empty()) {
    ::close(fd_);
    fd_ = -1;
  }
}

ChangeEvents::~ChangeEvents() {
  if (fd_ >= 0) ::close(fd_);
}

ChangeEvent ChangeEvents::read_events() {
  // Room for many events at once: each is a header and a name of at most NAME_MAX + 1 bytes.
  alignas(inotify_event) char buffer[64 * 1024];
  ChangeEvent last = ChangeEvent::none;
  for (;;) {
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n <= 0) return last;  // none left (EAGAIN), or an error: polling still sees the change
    for (ssize_t at = 0; at < n;) {
      const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
      at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
      const auto folder = folders_.find(event->wd);
      if (folder == folders_.end() || event->len == 0) continue;
      if (!files_.count(folder->second / event->name)) continue;
      last = (event->mask & kFinished) ? ChangeEvent::finished : ChangeEvent::changed;
    }
  }
}

ChangeEvent ChangeEvents::wait(double seconds, const std::atomic<bool>& stop) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (!stop) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count();
    if (left <= 0) return ChangeEvent::none;
    // In slices of at most 20 ms, so that a stop is seen soon.
    const int slice = static_cast<int>(std::min<long long>(left, 20));
    if (fd_ < 0) {
      ::poll(nullptr, 0, slice);
      continue;
    }
    pollfd readable{fd_, POLLIN, 0};
    if (::poll(&readable, 1, slice) > 0)
      if (const ChangeEvent event = read_events(); event != ChangeEvent::none) return event;
  }
  return ChangeEvent::none;
}

}  // namespace olt
