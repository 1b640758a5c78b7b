#pragma once
// File helpers. Every file OLT produces is written to a temporary sibling and renamed into place,
// so a killed run never leaves a half-written file under its final name.
#include <cstdint>
#include <filesystem>
#include <istream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace olt {

namespace fs = std::filesystem;

/// The largest file read_file accepts: inputs are read whole, so a huge file (a 10 GB "JSON")
/// is refused before any allocation.
inline constexpr uint64_t kMaxInputFileBytes = 256ull << 20;

/// Reads a whole file; throws InputError naming the file when it is missing, unreadable, a
/// folder, a symbolic link loop, or larger than kMaxInputFileBytes.
std::string read_file(const fs::path& file);

/// Opens a regular file for reading (never blocking on a named pipe or device); returns the file
/// descriptor and sets `size`. Throws InputError naming the file when it is missing, a folder, a
/// named pipe or another special file, or a symbolic link loop.
int open_regular_file(const fs::path& file, uint64_t* size);

/// A regular file's bytes as a stream read 64 KB at a time, for texts parsed as they come rather
/// than held whole (a stage's publish list: 12 MB at 10,000 frames). Opening fails as read_file
/// does (no size limit: nothing is held); a read error is an InputError naming the file, thrown from
/// the stream buffer.
std::unique_ptr<std::istream> open_file_stream(const fs::path& file);

/// The first `count` bytes of a file (fewer if it is shorter); errors as read_file.
std::string read_file_head(const fs::path& file, size_t count);

/// Whether `path` is a non-empty relative path without "." or ".." parts: joined to a folder, it
/// stays inside it (an output path from a publish list, a file an artifact refers to).
bool stays_inside(std::string_view path);
/// The part of `path` before its last slash: its folder, "" where it has none.
std::string_view folder_of(std::string_view path);
/// Whether `path` is a relative path in normal form (lexically_normal leaves it as it is; "a/" and
/// "." too, but they are not such names): none of its parts between slashes is empty, "." or "..".
bool already_normal(std::string_view path);

/// Writes `bytes` to `file` atomically (temporary sibling, flush, rename); creates parent folders.
void write_file_atomic(const fs::path& file, std::string_view bytes);

/// Writes all of `bytes` to an open file; returns 0, or the error number of the write that failed
/// (ENOSPC where the disk took nothing more; an injected one, see olt/core/fault.h).
int write_fully(int fd, std::string_view bytes);

/// Flushes everything written to the file systems holding `paths` (syncfs), each once: one call
/// makes a whole folder of files durable, where fsync per file costs a disk flush each. Throws
/// std::system_error where a sync failed, std::runtime_error where a path cannot be opened.
void sync_file_systems(const std::vector<fs::path>& paths);

/// A fresh path next to `target` for a temporary file or folder (unique per process and call):
/// `.tmp.<name>.<host>.<pid>.<n>` (the host, so that on a file system shared by several machines a
/// process judges only its own machine's temporaries: a pid means nothing elsewhere).
fs::path temp_sibling(const fs::path& target);

/// This machine's name as temp_sibling writes it (dots and slashes replaced).
const std::string& host_name();

/// `path` made absolute against `base` (when relative) and lexically normalised.
fs::path resolve_path(const fs::path& base, const fs::path& path);

}  // namespace olt
