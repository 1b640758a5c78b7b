#include "unit_engine.h"

#include <algorithm>
#include <atomic>
#include <functional>

#include "artifact_folder.h"
#include "explain.h"
#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/parallel.h"
#include "olt/core/process_memory.h"
#include "olt/core/progress.h"
#include "olt/runtime/runner.h"

namespace olt {
namespace {

// The stage's record of its units, beside its artifact ("frames.json"), for the next plan to compare.
std::string records_file(const UnitWords& words) { return words.unit + "s.json"; }

// A unit run into its entry, and whether it worked in place (from what was kept of its last run).
struct UnitRan {
  Artifact entry;
  bool in_place;
};

// Runs unit `i` into an entry of its own.
UnitRan run_unit(const UnitWork& work, size_t i, const std::string& key, const Store& store) {
  const fs::path dir = store.begin(key);
  try {
    ArtifactFolder out(dir, store.files());
    const bool in_place = work.run(i, out);
    Artifact stored = store.commit(key, dir, out.take_described());
    fault_point("unit_stored");
    return {std::move(stored), in_place};
  } catch (...) {
    store.discard(dir);
    throw;
  }
}

// Every unit `selected` selects (by position), found in the cache or run, in parallel, each entry
// handed to `take` as soon as it is there. What this run reused and ran, for the log. Once `stop`
// is set no unit is started or taken; those under way finish into the cache, then RunStopped says
// how many are left to run (those not in the cache: a stat each).
nlohmann::json find_or_run(const UnitWork& work, const UnitWords& words, const Store& store,
                           const std::function<bool(size_t)>& selected,
                           const std::function<void(size_t, const Artifact&)>& take, const std::atomic<bool>* stop) {
  const auto& units = work.units();
  std::atomic<int> ran{0}, reused{0}, in_place{0}, left{0};
  size_t selected_count = 0;
  for (size_t i = 0; i < units.size(); ++i) selected_count += units[i] && selected(i);
  Progress progress(words.unit + "s " + words.done, selected_count);
  parallel_for(units.size(), [&](size_t i) {
    if (!units[i] || !selected(i)) return;
    const std::string key = unit_key(*units[i], words);
    if (stop && *stop) {  // the stage's artifact will not be made: no unit is taken, none started
      left += !store.holds(key);
      return;
    }
    std::optional<Artifact> entry = store.find(key);
    if (entry) {
      ++reused;
    } else {
      UnitRan unit = run_unit(work, i, key, store);
      entry = std::move(unit.entry);
      ++ran;
      in_place += unit.in_place;
    }
    take(i, *entry);
    progress.advance();
  });
  if (left > 0)
    throw RunStopped("with " + std::to_string(left.load()) + " of " + std::to_string(selected_count) + " " +
                     words.unit + "s left to " + words.verb);
  nlohmann::json report = {{words.unit + "s_" + words.done, ran.load()}, {words.unit + "s_reused", reused.load()}};
  if (in_place > 0) report[words.unit + "s_in_place"] = in_place.load();  // none on a shard: nothing kept
  return report;
}

// The units' records as one JSON object by unit name, a record a line in its compact text, written
// into `file` in pieces rather than copied into one document or held whole (5 MB at 10,000 frames).
void write_records(ArtifactWriter& out, const std::string& file, const UnitWork& work) {
  const auto& units = work.units();
  std::vector<size_t> sorted;  // places of the units, by name
  for (size_t i = 0; i < units.size(); ++i)
    if (units[i]) sorted.push_back(i);
  std::stable_sort(sorted.begin(), sorted.end(), [&](size_t a, size_t b) { return units[a]->name < units[b]->name; });
  out.write_pieces(file, [&](const PieceSink& sink) {
    Pieces pieces(sink);
    std::string& text = pieces.text();
    text = "{";
    bool any = false;
    for (size_t i = 0; i < sorted.size(); ++i) {
      const std::string& name = units[sorted[i]]->name;
      if (i + 1 < sorted.size() && units[sorted[i + 1]]->name == name) continue;  // the last of a name counts
      text += any ? ",\n " : "\n ";
      any = true;
      text += json_string(name) + ": " + work.record(sorted[i]);
      pieces.next();
    }
    text += any ? "\n}\n" : "}\n";
    pieces.flush();
  });
}

}  // namespace

std::string unit_key(const Unit& unit, const UnitWords& words) { return words.unit + "-" + unit.record_sha256.hex(); }

nlohmann::json run_units(UnitWork& work, const UnitWords& words, const Store& store, ArtifactWriter& out,
                         const std::atomic<bool>* stop, const std::string& kept_name) {
  nlohmann::json report = find_or_run(
      work, words, store, [](size_t) { return true; },
      [&](size_t i, const Artifact& entry) { work.take(i, entry, out); }, stop);
  if (!kept_name.empty() && keeping_memory()) {  // each edit's frames made again: those of the edit before let go
    std::vector<std::string> keys;
    for (const auto& unit : work.units())
      if (unit) keys.push_back(unit_key(*unit, words));
    store.forget_unused(kept_name, std::move(keys));
  }
  write_records(out, records_file(words), work);
  return report;
}

nlohmann::json run_shard_units(const UnitWork& work, const UnitWords& words, const Store& store, const Shard& shard,
                               const std::atomic<bool>* stop) {
  return find_or_run(
      work, words, store, [&](size_t i) { return shard.owns(i); }, [](size_t, const Artifact&) {}, stop);
}

void check_units_cached(const UnitWork& work, const UnitWords& words, const Store& store, const std::string& stage_id,
                        int shards) {
  std::vector<std::string> missing;
  const auto& units = work.units();
  for (size_t i = 0; i < units.size(); ++i)
    if (units[i] && !store.find(unit_key(*units[i], words)))
      missing.push_back(units[i]->name + " (shard " + std::to_string(i % static_cast<size_t>(shards)) + "/" +
                        std::to_string(shards) + ")");
  if (missing.empty()) return;
  std::string list;
  for (size_t i = 0; i < missing.size() && i < 5; ++i) list += (i ? ", " : "") + missing[i];
  throw ShardsIncomplete(std::to_string(missing.size()) + " unit(s) of stage '" + stage_id +
                         "' are not in the cache: " + list + (missing.size() > 5 ? ", ..." : "") +
                         "; the shards ran on other inputs, or their cache entries were removed");
}

namespace {

// What a plan says of a stage's units: how many run and are reused, units per cause, units per
// changed member they hold.
struct UnitsPlan {
  int to_run = 0, reused = 0;
  std::map<std::string, int> causes, members;
};

// "3 of 12 frames to label; 1: pose changed; frames seeing changed box b1 (2), b2 (1)".
std::string plan_text(const UnitsPlan& plan, const UnitWords& words) {
  const std::string plural = words.unit + "s";
  std::string text = std::to_string(plan.to_run) + " of " + std::to_string(plan.to_run + plan.reused) + " " + plural +
                     " to " + words.verb;
  for (const auto& [cause, count] : plan.causes) text += "; " + std::to_string(count) + ": " + cause;
  if (plan.members.empty()) return text;
  std::vector<std::pair<int, std::string>> ranked;
  for (const auto& [member, count] : plan.members) ranked.emplace_back(-count, member);
  std::sort(ranked.begin(), ranked.end());
  text += "; " + plural + " " + words.holding + " changed " + words.member;
  for (size_t i = 0; i < ranked.size() && i < 5; ++i)
    text += (i ? ", " : " ") + ranked[i].second + " (" + std::to_string(-ranked[i].first) + ")";
  if (ranked.size() > 5) text += " and " + std::to_string(ranked.size() - 5) + " more";
  return text;
}

}  // namespace

nlohmann::json explain_units(const UnitWork& work, const UnitWords& words, const Store& store,
                             const std::optional<Artifact>& previous) {
  nlohmann::json before = nlohmann::json::object();
  if (previous && previous->file(records_file(words)))
    before = nlohmann::json::parse(store.files().read(previous->path(records_file(words))));
  UnitsPlan plan;
  const auto& units = work.units();
  for (size_t i = 0; i < units.size(); ++i) {
    const std::optional<Unit>& unit = units[i];
    if (!unit) continue;
    if (store.find(unit_key(*unit, words))) {
      ++plan.reused;
      continue;
    }
    ++plan.to_run;
    if (!before.contains(unit->name)) {
      ++plan.causes["not in the previous run"];
      continue;
    }
    const RecordChange change =
        diff_records(nlohmann::json::parse(work.record(i)), before[unit->name], {words.members});
    std::string parts;
    for (const auto& part : change.parts) parts += (parts.empty() ? "" : ", ") + part;
    if (!parts.empty()) ++plan.causes[parts + " changed"];
    for (const auto& [part, changed] : change.members)
      for (const auto& member : changed) ++plan.members[member];
    if (change.empty()) ++plan.causes["not in the cache"];
  }
  const std::string plural = words.unit + "s";
  return {{plural + "_to_" + words.verb, plan.to_run},
          {plural + "_reused", plan.reused},
          {"causes", plan.causes},
          {plural + "_" + words.holding + "_changed_" + words.member, plan.members},
          {"text", plan_text(plan, words)}};
}

}  // namespace olt
