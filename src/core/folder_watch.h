#pragma once
// The real file system's FolderWatch (olt/core/file_system.h): inotify. Private to olt/core.
#include <memory>
#include <vector>

#include "olt/core/file_system.h"

namespace olt {

/// A watch over `folders` (not following a link); null when the system refuses one of them (a
/// folder missing, no inotify watches left).
std::unique_ptr<FolderWatch> watch_real_folders(const std::vector<fs::path>& folders);

}  // namespace olt
