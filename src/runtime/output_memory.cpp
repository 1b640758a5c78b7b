#include "output_memory.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <memory>

#include "manifest.h"
#include "olt/core/process_memory.h"

namespace olt {
namespace {

// A process that keeps memory remembers the digest of the manifest it published last under the
// manifest's path, with the file's identity (inode, size, time: a manifest replaced or edited is
// another file).
std::string manifest_memo_name(const fs::path& manifest) { return "manifest digest " + manifest.string(); }
std::string file_identity(const FileStat& st) {
  return std::to_string(st.identity) + " " + std::to_string(st.size) + " " + std::to_string(st.mtime_ns);
}

// The output as a publish left it: the watch begun then over its folders (thread-safe), the file
// system it was begun on, and the manifest it left.
struct OutputAsLeft {
  const FileSystem* files = nullptr;
  std::shared_ptr<FolderWatch> watch;
  FileStat manifest;
  uint64_t folder = 0;  ///< the output folder's inode when the watch began
};

std::string as_left_name(const fs::path& output) { return "output as left " + output.string(); }

}  // namespace

std::string existing_manifest_digest(const FileSystem& files, const fs::path& manifest, const FileStat& st) {
  if (keeping_memory() && st.is_file() && st.identity != 0)
    if (const auto known = remembered_from<std::string>(manifest_memo_name(manifest), file_identity(st))) return *known;
  return manifest_digest(files, manifest);
}

void remember_manifest_digest(const FileSystem& files, const fs::path& manifest, const std::string& digest,
                              const FileStat& known) {
  if (!keeping_memory() || digest.empty()) return;
  const FileStat st = files.stat(manifest);
  if (known.same_file(st))
    remember_from<std::string>(manifest_memo_name(manifest), file_identity(st),
                               std::make_shared<const std::string>(digest), sizeof(std::string) + digest.size());
}

bool as_left(const FileSystem& files, const fs::path& output, const FileStat& in_place) {
  if (!keeping_memory()) return false;
  const auto known = remembered<OutputAsLeft>(as_left_name(output));
  return known && known->files == &files && known->manifest.same_file(in_place) && !known->watch->changed();
}

void remember_as_left(FileSystem& files, const fs::path& output, const std::vector<fs::path>& folders,
                      const FileStat& manifest, bool was_as_left) {
  if (!keeping_memory()) return;
  const std::string name = as_left_name(output);
  const uint64_t folder = files.stat(output).identity;
  // The last watch begun again from now (its own publish's changes forgotten) rather than let go:
  // letting go of inotify watches waits for the kernel, up to 15 ms. Only where the publish found the
  // output as it was left, in the same folder: inotify follows folders, not paths, and an output
  // folder put in another's place (its parent moved, a link changed) would go on being watched where
  // it went. Else a new watch, the last let go first (its inotify watches count against the user's).
  std::shared_ptr<FolderWatch> watch;
  if (const auto known = remembered<OutputAsLeft>(name);
      known && was_as_left && known->files == &files && known->folder == folder && folder != 0)
    watch = known->watch;
  remember<OutputAsLeft>(name, nullptr, 0);
  if (!manifest.same_file(files.stat(output / "manifest.json"))) return;  // replaced meanwhile
  if (watch && !watch->restart(folders)) {
    spdlog::debug("{}: its watch begun anew (a folder it watched moved or removed, or events lost)", output.string());
    watch.reset();
  }
  if (!watch) watch = files.watch(folders);
  if (!watch) {
    static std::atomic<bool> said{false};
    if (!said.exchange(true))
      spdlog::info(
          "{}: its folders cannot be watched (a network file system, or no inotify watches left): each "
          "publish looks at every file there",
          output.string());
    return;
  }
  remember<OutputAsLeft>(name,
                         std::make_shared<const OutputAsLeft>(OutputAsLeft{&files, std::move(watch), manifest, folder}),
                         sizeof(OutputAsLeft) + folders.size() * 64);
}

}  // namespace olt
