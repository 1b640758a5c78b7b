#pragma once
// A publish's changes wait in `output/.olt-publish`, complete and durable, before the first is
// made: files/<path> to move into place, journal.json ({"put": [path], "gone": [{"path",
// "sha256"}]}), manifest.json. Renaming the folder, filled under a temporary name, to this one is the
// moment a publish happens: before it, nothing of the output has changed; after it, the changes are
// made, by this run or, killed, by the next.
#include <functional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "manifest.h"
#include "olt/core/file_system.h"
#include "olt/core/pieces.h"

namespace olt {

inline const char* const kPending = ".olt-publish";

/// journal.json: the paths to move into place from files/ (`put_count` of them, the i-th
/// `put(i)`), and the files to remove where they still hold the digest the last manifest listed;
/// handed to `sink` in pieces (80,000 paths at 10,000 observations: 6 MB not held whole).
void journal_pieces(size_t put_count, const std::function<std::string(size_t)>& put, const Listed& gone,
                    const PieceSink& sink);

/// Who left the changes apply_pending makes.
enum class Pending {
  left_by_a_run,  ///< a run killed while it published, or this one: each file looked for first
  /// this process staged them just now: every file to move is there, and none is looked for first (a
  /// stat each: 212 after a one-box edit of the robot); one that is not there fails its move, and the
  /// next run finishes the publish
  staged_now,
};

/// Makes the changes waiting in output/.olt-publish, then removes it. Each step can be made again (a
/// file already moved is not in files/ any more), so a run killed here is finished by the next.
/// Every folder on the way is checked before any file is moved.
void apply_pending(FileSystem& files, const fs::path& output, Pending pending = Pending::left_by_a_run);

/// Whether `path` (relative, safe) reaches into `output` through real folders only: no component
/// before the last is a symbolic link or a file. Missing folders are fine (publishing creates them).
/// `known` (optional) remembers the folders found real, so many files of one folder cost one stat.
bool through_real_folders(const FileSystem& files, const fs::path& output, const std::string& path,
                          std::set<fs::path>* known = nullptr);

}  // namespace olt
