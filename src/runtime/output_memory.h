#pragma once
// What a process that keeps memory (`olt watch`, olt/core/process_memory.h) knows of an output it
// published into, so that its next publish need not read again what it left there: the digest of
// the manifest it wrote, and whether anything changed in the output since. Private to the runtime.
#include <string>
#include <vector>

#include "olt/core/file_system.h"

namespace olt {

/// The digest of the output's manifest: its bytes hashed (31 MB at 80,000 files), or, in a process
/// that keeps memory, the one remembered when it published it, while it is the same file.
/// `st`: the manifest's stat, taken before.
std::string existing_manifest_digest(const FileSystem& files, const fs::path& manifest, const FileStat& st);

/// Remembers that the output's manifest is the one of `digest`: `known`, the file whose digest that
/// is, stat-ed before (the manifest staged, or the one found in place), if it is still the file there
/// (another job publishing into the output could have replaced it meanwhile: it is then hashed next
/// time).
void remember_manifest_digest(const FileSystem& files, const fs::path& manifest, const std::string& digest,
                              const FileStat& known);

/// Whether the output is as this process's last publish into it left it: nothing made, written,
/// removed or moved in its folders since (a FolderWatch begun then), and `in_place`, the manifest
/// there now, the one it left. Every file that manifest lists is then as it was: a publish need not
/// look at each (a stat of each of 80,000 files was a sixth of an `olt watch` cycle that relabels no
/// frame at 10,000 observations). Never in a process that keeps no memory.
bool as_left(const FileSystem& files, const fs::path& output, const FileStat& in_place);

/// Remembers the output as a publish just left it, watched from now on: `folders`, the output's and
/// every folder it publishes into or through; `manifest`, the manifest it left (if another job has
/// replaced it meanwhile, nothing is remembered). A change made while the publish ran, after it
/// looked, is not seen (the next `olt run` puts it right). Where the folders cannot be watched (a
/// network file system, no inotify watches left), nothing is remembered, and each publish looks.
/// `was_as_left`: the publish found the output as the last one left it (as_left); then the watch
/// that one remembered is begun again (FolderWatch::restart) where it can be.
void remember_as_left(FileSystem& files, const fs::path& output, const std::vector<fs::path>& folders,
                      const FileStat& manifest, bool was_as_left);

}  // namespace olt
