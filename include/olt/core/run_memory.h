#pragma once
// What a run made of the files it wrote, kept by each file's digest for the rest of the run, in a
// process that keeps memory (`olt watch`): the files' bytes, so that publishing writes them without
// reading each cache file back and hashing it again, and what a stage parsed of a file for a later
// stage (the labeling stage's COCO masks, which the export would read and parse again). A digest
// names the bytes, so nothing kept can stand in for other content. Kept up to kRunMemoryBudget a
// run (not counted in the process's budget for what it keeps between runs); let go at the run's end.
#include <cstddef>
#include <memory>
#include <string>
#include <typeindex>

namespace olt {

/// What a run may keep: a full relabel of the synthetic robot (320 frames at 640x480) writes about
/// 12 MB of files, a one-box edit about 4 MB.
constexpr size_t kRunMemoryBudget = size_t{32} << 20;
/// What a value kept takes of it besides its own bytes: its digest, the map's node, its control block.
constexpr size_t kRunMemoryEntryBytes = 256;

namespace detail {
void keep_for_run_any(const std::string& sha256, std::type_index type, std::shared_ptr<const void> value, size_t bytes);
std::shared_ptr<const void> kept_for_run_any(const std::string& sha256, std::type_index type);
}  // namespace detail

/// `value` (holding `bytes`), made of the file with digest `sha256` (hex), kept for the rest of the
/// run where the process keeps memory and the run's budget has room for it (and kRunMemoryEntryBytes);
/// one value of a type a digest (the first kept). Thread-safe.
template <class T>
void keep_for_run(const std::string& sha256, std::shared_ptr<const T> value, size_t bytes) {
  detail::keep_for_run_any(sha256, typeid(T), std::move(value), bytes);
}

/// The value of type T kept for the file with digest `sha256` (hex), or null. Thread-safe.
template <class T>
std::shared_ptr<const T> kept_for_run(const std::string& sha256) {
  return std::static_pointer_cast<const T>(detail::kept_for_run_any(sha256, typeid(T)));
}

/// How many more bytes this run may keep: none where the process keeps nothing.
size_t run_memory_room();

/// Lets everything kept go: at a run's start and end (not while the run's stages keep values).
void forget_run_memory();

}  // namespace olt
