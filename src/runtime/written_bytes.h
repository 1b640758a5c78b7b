#pragma once
// What a run wrote into the cache, kept by digest in a process that keeps memory (`olt watch`), so
// that publishing writes those files from memory instead of reading each cache file back and
// hashing it again. After a one-box edit the robot publishes the 212 files it has just written, and
// their copies were 8 % of the cycle.
// The bytes are kept as they were hashed when written (ArtifactFolder), so a digest names them.
// They are kept up to a budget per run, and let go at the run's end.
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace olt {

/// Keeps a copy of `bytes`, written into the cache under digest `sha256` (hex), where the process
/// keeps memory and the run's budget has room for them. Thread-safe.
void keep_written(const std::string& sha256, std::string_view bytes);
/// How many more bytes this run may keep: none where the process keeps nothing.
size_t written_room();
/// The bytes this run wrote under `sha256` (hex), or null where none are kept (none are where the
/// process keeps nothing). Thread-safe.
std::shared_ptr<const std::string> written_bytes(const std::string& sha256);
/// Lets every kept file go: at a run's start and end.
void forget_written();

}  // namespace olt
