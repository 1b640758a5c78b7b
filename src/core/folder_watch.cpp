#include "folder_watch.h"

#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>

namespace olt {
namespace {

// Everything that changes what a folder holds or what its files hold; reading them is not a change.
constexpr uint32_t kChanges = IN_MODIFY | IN_ATTRIB | IN_CLOSE_WRITE | IN_CREATE | IN_DELETE | IN_MOVED_FROM |
                              IN_MOVED_TO | IN_DELETE_SELF | IN_MOVE_SELF;

// Any event at all is a change (IN_IGNORED, a watch gone with its folder, and IN_Q_OVERFLOW
// included): the events themselves are never read for what they say.
class InotifyWatch : public FolderWatch {
 public:
  explicit InotifyWatch(int fd) : fd_(fd) {}
  InotifyWatch(const InotifyWatch&) = delete;
  InotifyWatch& operator=(const InotifyWatch&) = delete;
  ~InotifyWatch() override { ::close(fd_); }

  bool changed() override {
    if (changed_) return true;
    alignas(inotify_event) char events[4096];
    ssize_t n;
    do n = ::read(fd_, events, sizeof events);
    while (n < 0 && errno == EINTR);
    changed_ = n > 0 || (n < 0 && errno != EAGAIN);  // an error other than "none waiting" is a doubt
    return changed_;
  }

 private:
  int fd_;
  bool changed_ = false;
};

}  // namespace

std::unique_ptr<FolderWatch> watch_real_folders(const std::vector<fs::path>& folders) {
  const int fd = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd < 0) return nullptr;
  auto watch = std::make_unique<InotifyWatch>(fd);
  for (const fs::path& folder : folders)
    if (::inotify_add_watch(fd, folder.c_str(), kChanges | IN_ONLYDIR | IN_DONT_FOLLOW) < 0) return nullptr;
  return watch;
}

}  // namespace olt
