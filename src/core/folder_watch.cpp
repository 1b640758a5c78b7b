#include "folder_watch.h"

#include <linux/magic.h>
#include <sys/inotify.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <set>
#include <string>

namespace olt {
namespace {

// Everything that changes what a folder holds or what its files hold; reading them is not a change.
constexpr uint32_t kChanges = IN_MODIFY | IN_ATTRIB | IN_CLOSE_WRITE | IN_CREATE | IN_DELETE | IN_MOVED_FROM |
                              IN_MOVED_TO | IN_DELETE_SELF | IN_MOVE_SELF;

// Whether `folder` lies on a file system whose every change passes through this machine's kernel,
// so that inotify reports it: not a network one (NFS, SMB, Ceph), where another machine's change is
// never reported, nor FUSE or 9p, which may not report theirs.
bool local_file_system(const fs::path& folder) {
  struct statfs st {};
  if (::statfs(folder.c_str(), &st) != 0) return false;
  switch (static_cast<unsigned long>(st.f_type)) {
    case EXT4_SUPER_MAGIC:  // ext2, ext3 and ext4 alike
    case XFS_SUPER_MAGIC:
    case BTRFS_SUPER_MAGIC:
    case TMPFS_MAGIC:
    case F2FS_SUPER_MAGIC:
    case OVERLAYFS_SUPER_MAGIC:  // a container's own layer
    case 0x2fc12fc1:             // ZFS (not in linux/magic.h)
      return true;
    default:
      return false;
  }
}

// Any event at all is a change (IN_IGNORED, a watch gone with its folder, and IN_Q_OVERFLOW
// included); what the events say matters only to whether the watch can begin again.
class InotifyWatch : public FolderWatch {
 public:
  explicit InotifyWatch(int fd) : fd_(fd) {}
  InotifyWatch(const InotifyWatch&) = delete;
  InotifyWatch& operator=(const InotifyWatch&) = delete;
  // Closing waits for the kernel to let go of the watches (an RCU grace period: up to 15 ms, up to a fifth of a
  // one-box cycle on the synthetic robot); a watch that begins again is not closed.
  ~InotifyWatch() override { ::close(fd_); }

  bool changed() override {
    const std::lock_guard<std::mutex> lock(mutex_);  // one reader: an event read is seen by all
    changed_ = changed_ || read_events();
    return changed_;
  }

  bool restart(const std::vector<fs::path>& folders) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    while (!lost_ && read_events()) {
    }
    if (lost_) return false;
    for (const fs::path& folder : folders)
      if (!watched_.count(folder.native()) && !add(folder)) return false;
    changed_ = false;
    return true;
  }

  // Watches `folder` too; false when it cannot be (not on a local file system, or refused).
  bool add(const fs::path& folder) {
    if (!local_file_system(folder) ||
        ::inotify_add_watch(fd_, folder.c_str(), kChanges | IN_ONLYDIR | IN_DONT_FOLLOW) < 0)
      return false;
    watched_.insert(folder.native());
    return true;
  }

 private:
  // Reads the events waiting (a buffer's worth); whether there were any. One that says a watched
  // folder is gone or moved (its watch no longer follows its path), events lost, or an error other
  // than "none waiting", and the watch has lost track of what it watches.
  bool read_events() {
    alignas(inotify_event) char events[4096];
    ssize_t n;
    do n = ::read(fd_, events, sizeof events);
    while (n < 0 && errno == EINTR);
    if (n < 0 && errno == EAGAIN) return false;
    if (n <= 0) return lost_ = true;
    for (ssize_t at = 0; at < n;) {
      inotify_event event{};
      std::memcpy(&event, events + at, sizeof event);
      if (event.mask & (IN_IGNORED | IN_Q_OVERFLOW | IN_DELETE_SELF | IN_MOVE_SELF | IN_UNMOUNT)) lost_ = true;
      at += static_cast<ssize_t>(sizeof event + event.len);
    }
    return true;
  }

  int fd_;
  std::mutex mutex_;
  bool changed_ = false;
  bool lost_ = false;
  std::set<std::string> watched_;  // the folders' paths
};

}  // namespace

std::unique_ptr<FolderWatch> watch_real_folders(const std::vector<fs::path>& folders) {
  const int fd = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd < 0) return nullptr;
  auto watch = std::make_unique<InotifyWatch>(fd);
  for (const fs::path& folder : folders)
    if (!watch->add(folder)) return nullptr;
  return watch;
}

}  // namespace olt
