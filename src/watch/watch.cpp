#include "olt/watch/watch.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>
#include <set>

#include "olt/core/error.h"
#include "olt/core/page_allocator.h"
#include "olt/core/process_memory.h"
#include "olt/core/usable_memory.h"
#include "olt/job/job.h"
#include "olt/watch/change_events.h"
#include "olt/watch/file_stamps.h"
#include "olt/watch/http_endpoint.h"
#include "olt/watch/watch_state.h"

namespace olt {
namespace {

using Clock = std::chrono::steady_clock;

double unix_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

// The files a run of the job reads, by stage id ("" for the job file and files errors named). A
// stage whose files cannot be listed now (its box file does not parse) keeps its earlier list, so
// the file being fixed stays watched.
struct WatchedFiles {
  std::map<std::string, std::vector<fs::path>> by_stage;

  std::vector<fs::path> all() const {
    std::set<fs::path> files;
    for (const auto& [stage, list] : by_stage) files.insert(list.begin(), list.end());
    return {files.begin(), files.end()};
  }
};

// The files of a job loaded to run (a job that does not load leaves the lists as they were).
void update_watched(WatchedFiles& watched, const Job& job) {
  for (const auto& [stage, files] : job.files_read) watched.by_stage[stage] = files;
}

// One run of the job, never throwing: the outcome and errors go into the cycle; `cache` becomes the
// job's cache where the run stored something in it (stages ran, or it failed after it began). Once
// `stop` is set, the run ends at its next frame or stage, or its wait for another process's lock:
// outcome "stopped", nothing published.
WatchCycle run_cycle(const fs::path& job_file, WatchedFiles& watched, std::optional<fs::path>& cache,
                     const std::atomic<bool>& stop) {
  WatchCycle cycle;
  cycle.started_unix_s = unix_now();
  const auto start = Clock::now();
  std::optional<fs::path> loaded_cache;
  try {
    const Job job = load_runnable_job(job_file);
    loaded_cache = job.cache;
    update_watched(watched, job);
    RunOptions options;
    options.stop = &stop;
    cycle.stages = run_job(job, options);
    cycle.outcome = "ok";
    if (std::any_of(cycle.stages.begin(), cycle.stages.end(), [](const StageStatus& s) { return s.status == "ran"; }))
      cache = job.cache;
    for (const auto& s : cycle.stages)
      if (s.status == "ran" && s.summary.is_object() && s.summary.contains("frames_labeled"))
        cycle.frames_relabeled += s.summary["frames_labeled"].get<long>();
  } catch (const RunStopped& e) {
    if (loaded_cache) cache = loaded_cache;
    cycle.outcome = "stopped";
    cycle.errors.push_back(e.what());
  } catch (const InputError& e) {
    if (loaded_cache) cache = loaded_cache;
    cycle.outcome = "invalid_input";
    for (const auto& d : e.diagnostics()) {
      cycle.errors.push_back(d.str());
      if (!d.file.empty() && fs::path(d.file).is_absolute()) watched.by_stage[""].push_back(d.file);
    }
  } catch (const std::exception& e) {
    if (loaded_cache) cache = loaded_cache;
    cycle.outcome = "stage_failed";
    cycle.errors.push_back(e.what());
  }
  cycle.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return cycle;
}

void log_cycle(const WatchCycle& c) {
  std::string trigger;
  for (const auto& f : c.trigger) trigger += (trigger.empty() ? "" : ", ") + fs::path(f).filename().string();
  std::string ran;
  for (const auto& s : c.stages)
    if (s.status == "ran") ran += (ran.empty() ? "" : ", ") + s.id;
  const std::string why = c.trigger.empty() ? "first run" : "changed: " + trigger;
  if (c.outcome == "ok") {
    spdlog::info("watch: cycle {} ({}): ok in {:.2f} s; ran {}; {} frames relabeled", c.number, why, c.seconds,
                 ran.empty() ? "nothing" : ran, c.frames_relabeled);
    return;
  }
  if (c.outcome == "stopped") {
    spdlog::info(
        "watch: cycle {} ({}): {} after {:.2f} s; the last good output stays in place, what the cycle "
        "finished is in the cache for the next start",
        c.number, why, c.errors.empty() ? "stopped" : c.errors.front(), c.seconds);
    return;
  }
  spdlog::error("watch: cycle {} ({}): {} after {:.2f} s; the last good output stays in place", c.number, why,
                c.outcome == "invalid_input" ? "invalid input" : "a stage failed", c.seconds);
  for (const auto& e : c.errors) spdlog::error("  {}", e);
}

// `fresh` (the files' stamps now) with the stamps of those already in `known` (stamped before the
// run read them, so a write during the run is still seen as a change).
FileStamps with_known(FileStamps fresh, const FileStamps& known) {
  for (auto& [file, stamp] : fresh)
    if (const auto it = known.find(file); it != known.end()) stamp = it->second;
  return fresh;
}

// The status endpoint (/healthz, /status, /metrics) on `listen`, reading `state` under `mutex`.
std::unique_ptr<HttpEndpoint> serve_status(const std::string& listen, std::mutex& mutex, WatchState& state) {
  const ListenAddress address = parse_listen_address(listen);
  const auto locked = [&mutex, &state](auto&& render) {
    return [&mutex, &state, render] {
      const std::lock_guard<std::mutex> lock(mutex);
      return render(state);
    };
  };
  HttpRoutes routes = {
      {"/healthz",
       [] {
         return HttpResponse{200, "text/plain; charset=utf-8", "ok\n"};
       }},
      {"/status", locked([](const WatchState& s) {
         return HttpResponse{200, "application/json", status_json(s).dump(2) + "\n"};
       })},
      {"/metrics", locked([](const WatchState& s) {
         return HttpResponse{200, "text/plain; version=0.0.4; charset=utf-8", metrics_text(s)};
       })},
  };
  auto endpoint = std::make_unique<HttpEndpoint>(address, std::move(routes));
  const std::lock_guard<std::mutex> lock(mutex);
  state.listen = address.host + ":" + std::to_string(endpoint->port());
  if (!is_loopback(address.host))
    spdlog::warn("watch: serving on {}, which is not a loopback address: other machines can read the status",
                 address.host);
  spdlog::info("watch: listening on http://{} (/healthz, /status, /metrics)", state.listen);
  return endpoint;
}

// A save every changed file's writer finished is acted on after this much quiet (the other files of
// the save), rather than after the settle time.
constexpr double kQuietAfterFinished_s = 0.03;

// Waits for a change of `files` from `stamps` (`now`: their stamps as the wait begins), then for
// it to settle: the files the same for settle_s (a tool still writing, several files written), or,
// where the system reported every changed file finished (closed after writing, renamed into place),
// nothing more for a moment. Returns their stamps then (or when stopped). The files are stamped
// every poll_interval_s, and when the system reports a file finished: polling sees what the system
// does not report (network file systems).
FileStamps next_change(ChangeEvents& events, const std::vector<fs::path>& files, const FileStamps& stamps,
                       FileStamps now, const WatchConfig& config, const std::atomic<bool>& stop) {
  while (now == stamps) {
    events.wait(config.poll_interval_s, stop);
    if (stop) return now;
    now = stamp_files(files);
  }
  for (auto settled = Clock::now(); !stop;) {
    const double quiet_s = std::chrono::duration<double>(Clock::now() - settled).count();
    if (quiet_s >= config.settle_s) break;
    const bool finished = events.finished(changed_files(stamps, now));
    const bool woke = events.wait(
        std::min(finished ? kQuietAfterFinished_s : config.poll_interval_s, config.settle_s - quiet_s), stop);
    if (stop) break;
    FileStamps again = stamp_files(files);
    if (again != now) {
      now = std::move(again);
      settled = Clock::now();
    } else if (finished && !woke) {
      break;
    }
  }
  return now;
}

// Whether `files` stay as `now` for `seconds`; `now` becomes their stamps when they change.
bool quiet_for(double seconds, ChangeEvents& events, const std::vector<fs::path>& files, FileStamps& now,
               const WatchConfig& config, const std::atomic<bool>& stop) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (!stop) {
    const double left = std::chrono::duration<double>(until - Clock::now()).count();
    if (left <= 0) return true;
    events.wait(std::min(config.poll_interval_s, left), stop);
    FileStamps again = stamp_files(files);
    if (again != now) {
      now = std::move(again);
      return false;
    }
  }
  return false;
}

// What no job's last run uses, removed from `cache` (each edit stores the frames it relabeled and
// the stages that ran: ~3 MB on a 320-observation robot). False when another process was using the
// cache: collected the next time the daemon is idle.
bool collect_garbage(const fs::path& cache, std::mutex& mutex, WatchState& state) {
  const auto start = Clock::now();
  std::optional<Store::Collection> c;
  try {
    c = collect_cache_garbage_unless_busy(cache);
  } catch (const std::exception& e) {  // a damaged entry, a folder it may not remove: olt cache gc says more
    spdlog::warn("watch: cache gc failed, tried again after the next run: {}", e.what());
    return true;
  }
  if (!c) return false;
  spdlog::info("watch: cache gc: removed {} entries no run uses ({:.1f} MB) in {:.2f} s; kept {}", c->removed,
               static_cast<double>(c->bytes_freed) / 1e6, std::chrono::duration<double>(Clock::now() - start).count(),
               c->kept);
  const std::lock_guard<std::mutex> lock(mutex);
  ++state.cache_gc.count;
  state.cache_gc.entries_removed += static_cast<long>(c->removed);
  state.cache_gc.bytes_freed += c->bytes_freed;
  state.cache_gc.last_unix_s = unix_now();
  return true;
}

}  // namespace

size_t default_image_memory_mb(uint64_t usable) {
  if (usable == 0) return kImageMemoryFloorMb;
  const size_t floor = std::min<size_t>(kImageMemoryFloorMb, usable / 4 >> 20);
  return std::clamp<size_t>(usable / 8 >> 20, floor, kImageMemoryCeilingMb);
}

int watch_job(const WatchConfig& config, const std::atomic<bool>& stop) {
  const fs::path job_file = fs::absolute(config.job).lexically_normal();
  std::mutex mutex;
  WatchState state;
  if (config.image_memory_mb) {
    state.image_memory_mb = *config.image_memory_mb;
    state.image_memory_why = "--image-memory=" + std::to_string(state.image_memory_mb);
  } else {
    const MemoryAmount usable = usable_memory();
    state.image_memory_mb = default_image_memory_mb(usable.bytes);
    const std::string bounds = ", from " + std::to_string(kImageMemoryFloorMb) + " MB (at most a quarter) to " +
                               std::to_string(kImageMemoryCeilingMb) + " MB; --image-memory=MB sets it";
    state.image_memory_why =
        (usable.bytes ? "an eighth of " + usable.why : "the memory this process may use unknown") + bounds;
  }
  keep_in_memory(state.image_memory_mb << 20);
  // Lists freed are kept mapped for the next cycle's lists of the same sizes, up to an eighth of
  // the images' budget and at most 64 MB (olt/core/page_allocator.h: 150 page faults a cycle on the
  // robot).
  keep_freed_pages(std::min(state.image_memory_mb << 20, size_t{512} << 20) / 8);
  spdlog::info("watch: keeping up to {} MB of decoded images and labeled frames between cycles ({})",
               state.image_memory_mb, state.image_memory_why);
  state.job = job_file.string();
  state.started_unix_s = unix_now();
  const auto endpoint = config.listen.empty() ? nullptr : serve_status(config.listen, mutex, state);

  WatchedFiles watched;
  watched.by_stage[""] = {job_file};
  FileStamps stamps = stamp_files(watched.all());
  std::vector<std::string> trigger;
  std::optional<fs::path> garbage_in;  // the cache a cycle stored something in since the last collection
  for (int number = 1; !stop; ++number) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      state.running = true;
    }
    WatchCycle cycle = run_cycle(job_file, watched, garbage_in, stop);
    cycle.number = number;
    cycle.trigger = trigger;
    log_cycle(cycle);
    const std::vector<fs::path> files = watched.all();
    // Listening before the daemon says it is idle (no edit after is missed); stamped after that
    // (a change made while the job ran shows).
    ChangeEvents events(files, config.events);
    FileStamps now = stamp_files(files);
    stamps = with_known(now, stamps);
    {
      const std::lock_guard<std::mutex> lock(mutex);
      state.running = false;
      state.watched_files = files.size();
      state.image_memory_held = kept_memory();
      state.freed_pages_held = freed_pages_kept();
      record_cycle(state, std::move(cycle));
    }
    if (number == 1)
      spdlog::info("watch: watching {} files ({} folders told by the system, the rest polled every {} s); Ctrl-C stops",
                   files.size(), events.folders(), config.poll_interval_s);
    while (garbage_in && config.gc_idle_s > 0 && now == stamps &&
           quiet_for(config.gc_idle_s, events, files, now, config, stop))
      if (collect_garbage(*garbage_in, mutex, state)) garbage_in.reset();
    now = next_change(events, files, stamps, std::move(now), config, stop);
    trigger.clear();
    for (const auto& f : changed_files(stamps, now)) trigger.push_back(f.string());
    stamps = std::move(now);
  }
  spdlog::info("watch: stopped");
  return kExitOk;
}

}  // namespace olt
