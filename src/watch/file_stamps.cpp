#include "olt/watch/file_stamps.h"

#include <sys/stat.h>

namespace olt {

FileStamps stamp_files(const std::vector<std::filesystem::path>& files) {
  FileStamps stamps;
  for (const auto& file : files) {
    struct stat st {};
    FileStamp& stamp = stamps[file];
    if (::stat(file.c_str(), &st) != 0) continue;
    stamp.exists = true;
    stamp.size = static_cast<std::uintmax_t>(st.st_size);
    stamp.mtime_ns = static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
    stamp.inode = st.st_ino;
  }
  return stamps;
}

std::vector<std::filesystem::path> changed_files(const FileStamps& before, const FileStamps& after) {
  std::vector<std::filesystem::path> changed;
  for (const auto& [file, stamp] : after) {
    const auto it = before.find(file);
    if (it == before.end() || it->second != stamp) changed.push_back(file);
  }
  for (const auto& [file, stamp] : before)
    if (!after.count(file)) changed.push_back(file);
  return changed;
}

}  // namespace olt
