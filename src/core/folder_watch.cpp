#include "folder_watch.h"

#include <linux/magic.h>
#include <sys/inotify.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <cerrno>
#include <mutex>

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
// included): the events themselves are never read for what they say.
class InotifyWatch : public FolderWatch {
 public:
  explicit InotifyWatch(int fd) : fd_(fd) {}
  InotifyWatch(const InotifyWatch&) = delete;
  InotifyWatch& operator=(const InotifyWatch&) = delete;
  ~InotifyWatch() override { ::close(fd_); }

  bool changed() override {
    const std::lock_guard<std::mutex> lock(mutex_);  // one reader: an event read is seen by all
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
  std::mutex mutex_;
  bool changed_ = false;
};

}  // namespace

std::unique_ptr<FolderWatch> watch_real_folders(const std::vector<fs::path>& folders) {
  for (const fs::path& folder : folders)
    if (!local_file_system(folder)) return nullptr;
  const int fd = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd < 0) return nullptr;
  auto watch = std::make_unique<InotifyWatch>(fd);
  for (const fs::path& folder : folders)
    if (::inotify_add_watch(fd, folder.c_str(), kChanges | IN_ONLYDIR | IN_DONT_FOLLOW) < 0) return nullptr;
  return watch;
}

}  // namespace olt
