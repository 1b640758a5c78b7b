#pragma once
// `olt watch JOB`: the annotation loop's daemon. It runs the job, then watches the files the job
// reads (the job file, annotation files, trajectories, recording lists and images, any file an
// error named: the system's reports of changes, and polling) and, once a change has settled, runs
// the job again: the cache makes that re-run do only what the change touches (for a box edit, the
// frames that see the box). A failed run leaves the last good output in place; the daemon logs the
// error, reports it on /status and /metrics, and keeps watching.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace olt {

struct WatchConfig {
  std::filesystem::path job;
  std::string listen;  ///< PORT, HOST:PORT or [IPV6]:PORT for /healthz, /status, /metrics; "" none
  /// How often the watched files are stat()ed, seconds (also when the system reports one finished).
  double poll_interval_s = 0.2;
  /// A change is acted on once the files stayed the same this long, seconds; a save the system
  /// reports finished (closed after writing, renamed into place), 30 ms after it.
  double settle_s = 0.3;
  /// Whether the system's reports of changes (inotify) are listened to; false: polling alone
  /// (`--poll-only`, for a file system that reports changes wrongly).
  bool events = true;
  /// Decoded depth and colour images and labeled frames kept between cycles, MB: a cycle mostly
  /// relabels the frames the last one did (the same box moved again), and decoding them is about half
  /// of that work. nullopt: default_image_memory_mb of the memory this process may use.
  std::optional<size_t> image_memory_mb;
  /// Once the daemon has been idle this long after a cycle that stored something, seconds, it
  /// removes from the cache what no job's last run uses (as `olt cache gc`), unless another process
  /// is using the cache then; an edit made meanwhile waits for it. 0: never (`--no-gc`).
  double gc_idle_s = 10;
};

/// The bounds of what `olt watch` keeps between cycles unless told, MB (MiB, as every MB here).
inline constexpr size_t kImageMemoryFloorMb = 512, kImageMemoryCeilingMb = 4096;

/// What `olt watch` keeps between cycles unless told, MB: an eighth of the memory this process may
/// use (`usable`, bytes: the machine's, or its cgroup's limit), from kImageMemoryFloorMb (but never
/// more than a quarter of it) to kImageMemoryCeilingMb; the floor where unknown (0). A 640x480 frame
/// with its images takes 2.8 to 4 MB: 3 GB holds some 800 of them.
size_t default_image_memory_mb(uint64_t usable);

/// Watches and runs until `stop` becomes true (a cycle under way is finished first, so no output is
/// left half-published). Returns the exit code: 0 after a stop; throws InputError for a bad
/// configuration (such as an address that cannot be parsed) before anything runs.
int watch_job(const WatchConfig& config, const std::atomic<bool>& stop);

}  // namespace olt
