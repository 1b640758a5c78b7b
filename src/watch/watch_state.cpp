#include "olt/watch/watch_state.h"

#include <sstream>

namespace olt {
namespace {

// Prometheus label values escape backslash, double quote and newline.
std::string label_value(const std::string& value) {
  std::string out;
  for (char c : value) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

void family(std::ostringstream& out, const char* name, const char* type, const char* help) {
  out << "# HELP " << name << ' ' << help << "\n# TYPE " << name << ' ' << type << '\n';
}

nlohmann::json cycle_json(const WatchCycle& c) {
  nlohmann::json stages = nlohmann::json::array(), warnings = nlohmann::json::array();
  for (const auto& s : c.stages) {
    stages.push_back(
        {{"id", s.id}, {"kind", s.kind}, {"status", s.status}, {"reason", s.reason}, {"seconds", s.seconds}});
    // A stage's warnings (a box no frame sees, angles in the wrong unit), from its summary: a cached
    // stage's too, so a warning stays on /status until the box is fixed.
    if (s.summary.is_object() && s.summary.contains("warnings"))
      for (const auto& w : s.summary["warnings"]) warnings.push_back(s.id + ": " + w.get<std::string>());
  }
  return {{"cycle", c.number},
          {"started_unix_s", c.started_unix_s},
          {"seconds", c.seconds},
          {"outcome", c.outcome},
          {"errors", c.errors},
          {"warnings", warnings},
          {"trigger", c.trigger},
          {"stages", stages},
          {"frames_relabeled", c.frames_relabeled}};
}

}  // namespace

void record_cycle(WatchState& state, WatchCycle cycle) {
  ++state.runs;
  if (cycle.outcome == "ok")
    state.last_success_unix_s = cycle.started_unix_s + cycle.seconds;
  else if (cycle.outcome != "stopped")  // by a signal: how the daemon ends, not a failure
    ++state.failures[cycle.outcome];
  state.frames_relabeled += cycle.frames_relabeled;
  for (const auto& s : cycle.stages) {
    if (s.status != "ran") continue;
    StageTotals& totals = state.stage_totals[s.id];
    totals.kind = s.kind;
    ++totals.runs;
    totals.seconds_total += s.seconds;
    totals.last_seconds = s.seconds;
  }
  state.last = std::move(cycle);
}

nlohmann::json status_json(const WatchState& state) {
  nlohmann::json failures = nlohmann::json::object();
  for (const auto& [reason, n] : state.failures) failures[reason] = n;
  return {{"job", state.job},
          {"listen", state.listen},
          {"started_unix_s", state.started_unix_s},
          {"state", state.running ? "running" : "idle"},
          {"watched_files", state.watched_files},
          {"runs", state.runs},
          {"failures", failures},
          {"frames_relabeled", state.frames_relabeled},
          {"last_success_unix_s", state.last_success_unix_s},
          {"cache_gc",
           {{"collections", state.cache_gc.count},
            {"entries_removed", state.cache_gc.entries_removed},
            {"bytes_freed", state.cache_gc.bytes_freed},
            {"last_unix_s", state.cache_gc.last_unix_s}}},
          {"image_memory",
           {{"mb", state.image_memory_mb},
            {"why", state.image_memory_why},
            {"held_mb", static_cast<double>(state.image_memory_held.bytes) / (1 << 20)},
            {"values", state.image_memory_held.values},
            {"dropped", state.image_memory_held.dropped},
            {"freed_pages_mb", static_cast<double>(state.freed_pages_held) / (1 << 20)}}},
          {"last_run", state.last ? cycle_json(*state.last) : nlohmann::json()}};
}

std::string metrics_text(const WatchState& state) {
  std::ostringstream out;
  out.precision(15);
  family(out, "olt_watch_runs_total", "counter", "Runs of the job started by olt watch.");
  out << "olt_watch_runs_total " << state.runs << '\n';
  family(out, "olt_watch_run_failures_total", "counter",
         "Runs that failed: invalid_input (a bad job or input file), stage_failed (a stage broke).");
  for (const char* reason : {"invalid_input", "stage_failed"}) {
    const auto it = state.failures.find(reason);
    out << "olt_watch_run_failures_total{reason=\"" << reason << "\"} " << (it == state.failures.end() ? 0 : it->second)
        << '\n';
  }
  family(out, "olt_watch_frames_relabeled_total", "counter",
         "Observations labeled again (not reused from the cache), all runs.");
  out << "olt_watch_frames_relabeled_total " << state.frames_relabeled << '\n';
  family(out, "olt_watch_stage_runs_total", "counter", "Times each stage ran (was not cached).");
  for (const auto& [id, t] : state.stage_totals)
    out << "olt_watch_stage_runs_total{stage=\"" << label_value(id) << "\",kind=\"" << label_value(t.kind) << "\"} "
        << t.runs << '\n';
  family(out, "olt_watch_stage_duration_seconds_total", "counter", "Time spent running each stage, all runs.");
  for (const auto& [id, t] : state.stage_totals)
    out << "olt_watch_stage_duration_seconds_total{stage=\"" << label_value(id) << "\",kind=\"" << label_value(t.kind)
        << "\"} " << t.seconds_total << '\n';
  family(out, "olt_watch_stage_last_duration_seconds", "gauge", "Duration of each stage's last run.");
  for (const auto& [id, t] : state.stage_totals)
    out << "olt_watch_stage_last_duration_seconds{stage=\"" << label_value(id) << "\",kind=\"" << label_value(t.kind)
        << "\"} " << t.last_seconds << '\n';
  family(out, "olt_watch_last_run_success", "gauge", "1 when the last run succeeded, 0 when it failed.");
  out << "olt_watch_last_run_success " << (state.last && state.last->outcome == "ok" ? 1 : 0) << '\n';
  family(out, "olt_watch_last_success_timestamp_seconds", "gauge",
         "Unix time the last successful run finished (0: none yet).");
  out << "olt_watch_last_success_timestamp_seconds " << state.last_success_unix_s << '\n';
  family(out, "olt_watch_running", "gauge", "1 while a run is under way.");
  out << "olt_watch_running " << (state.running ? 1 : 0) << '\n';
  family(out, "olt_watch_cache_gc_total", "counter",
         "Times the daemon removed what no job's last run uses from the cache.");
  out << "olt_watch_cache_gc_total " << state.cache_gc.count << '\n';
  family(out, "olt_watch_cache_gc_bytes_freed_total", "counter", "Bytes those collections freed.");
  out << "olt_watch_cache_gc_bytes_freed_total " << state.cache_gc.bytes_freed << '\n';
  family(out, "olt_watch_image_memory_bytes", "gauge",
         "Decoded images and labeled frames kept between runs, after the last run (at most --image-memory).");
  out << "olt_watch_image_memory_bytes " << state.image_memory_held.bytes << '\n';
  family(out, "olt_watch_image_memory_dropped_total", "counter",
         "Values let go, or never kept, to stay within --image-memory, since the daemon began.");
  out << "olt_watch_image_memory_dropped_total " << state.image_memory_held.dropped << '\n';
  return out.str();
}

}  // namespace olt
