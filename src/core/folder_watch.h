#pragma once
// The real file system's FolderWatch (olt/core/file_system.h): inotify. Private to olt/core.
#include <memory>
#include <vector>

#include "olt/core/file_system.h"

namespace olt {

/// A watch over `folders` (not following a link); null when one of them is not on a local file
/// system (a change made by another machine to a network one is never reported) or the system
/// refuses it (a folder missing, no inotify watches left).
std::unique_ptr<FolderWatch> watch_real_folders(const std::vector<fs::path>& folders);

}  // namespace olt
