#include "unit_engine.h"

#include <algorithm>
#include <atomic>
#include <functional>
#include <map>
#include <set>

#include "artifact_folder.h"
#include "explain.h"
#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/parallel.h"
#include "olt/core/progress.h"

namespace olt {
namespace {

// The stage's record of its units, beside its artifact ("frames.json"), for the next plan to compare.
std::string records_file(const UnitWords& words) { return words.unit + "s.json"; }

// Runs unit `i` into an entry of its own, committed without syncing (the caller syncs once);
// `patched`: whether it built on `previous`.
Artifact run_unit(const UnitWork& work, size_t i, const std::string& key, const Store& store,
                  const PreviousUnit* previous, bool* patched) {
  const fs::path dir = store.begin(key);
  try {
    ArtifactFolder out(dir, store.files());
    *patched = work.run(i, previous, out);
    Artifact stored = store.commit(key, dir, out.take_referred(), /*durable=*/false);
    fault_point("unit_stored");
    return stored;
  } catch (...) {
    store.discard(dir);
    throw;
  }
}

// The records of the units named in `names` that the stage's previous artifact holds, by name (the
// others are skipped as they are read: at 10,000 frames the whole file is megabytes). None when the
// artifact has no records or they cannot be read (removed meanwhile): the units then start afresh.
std::map<std::string, nlohmann::json> previous_records(const Artifact& stage, const UnitWords& words,
                                                       const Store& store, const std::set<std::string>& names) {
  std::map<std::string, nlohmann::json> records;
  if (names.empty() || !stage.file(records_file(words))) return records;
  try {
    const nlohmann::json kept = nlohmann::json::parse(
        store.files().read(stage.path(records_file(words))),
        [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
          return depth != 1 || event != nlohmann::json::parse_event_t::key || names.count(parsed.get<std::string>());
        });
    for (auto& [name, record] : kept.items()) records.emplace(name, record);
  } catch (const std::exception&) {
    records.clear();
  }
  return records;
}

// Every unit `take` selects (by position), found in the cache or run, in parallel; a unit that runs
// is given its previous run's entry where `previous_stage` has one. The file system synced once
// after the units run.
UnitsDone find_or_run(const UnitWork& work, const UnitWords& words, const Store& store,
                      const std::function<bool(size_t)>& take, const std::optional<Artifact>& previous_stage) {
  const auto& units = work.units();
  std::vector<std::optional<Artifact>> entries(units.size());
  std::vector<std::string> keys(units.size());
  parallel_for(units.size(), [&](size_t i) {
    if (!units[i] || !take(i)) return;
    keys[i] = unit_key(*units[i], words);
    entries[i] = store.find(keys[i]);
  });
  std::vector<size_t> missing;
  std::set<std::string> missing_names;
  size_t taken = 0;
  for (size_t i = 0; i < units.size(); ++i) {
    if (!units[i] || !take(i)) continue;
    ++taken;
    if (entries[i]) continue;
    missing.push_back(i);
    missing_names.insert(units[i]->name);
  }
  std::map<std::string, nlohmann::json> records;
  if (previous_stage) records = previous_records(*previous_stage, words, store, missing_names);
  std::atomic<int> patched{0};
  Progress progress(words.unit + "s " + words.done, taken);
  progress.advance(taken - missing.size());
  parallel_for(missing.size(), [&](size_t m) {
    const size_t i = missing[m];
    std::optional<PreviousUnit> previous;
    if (const auto record = records.find(units[i]->name); record != records.end())
      if (const auto entry = store.find(unit_key(Unit{units[i]->name, record->second}, words)))
        previous.emplace(PreviousUnit{record->second, *entry, *previous_stage});
    bool built_on_previous = false;
    entries[i] = run_unit(work, i, keys[i], store, previous ? &*previous : nullptr, &built_on_previous);
    patched += built_on_previous;
    progress.advance();
  });
  if (!missing.empty()) store.files().sync(store.root());
  const int ran = static_cast<int>(missing.size()), reused = static_cast<int>(taken - missing.size());
  nlohmann::json report = {{words.unit + "s_" + words.done, ran}, {words.unit + "s_reused", reused}};
  if (patched > 0) report[words.unit + "s_patched"] = patched.load();  // none on a shard
  return {std::move(entries), std::move(report)};
}

// The units' records as one JSON object by unit name (as dump(1) of it writes it), written a record at
// a time rather than copied into one document.
std::string records_text(const std::vector<std::optional<Unit>>& units) {
  std::vector<const Unit*> sorted;
  for (const auto& unit : units)
    if (unit) sorted.push_back(&*unit);
  std::stable_sort(sorted.begin(), sorted.end(), [](const Unit* a, const Unit* b) { return a->name < b->name; });
  std::string text = "{";
  for (size_t i = 0; i < sorted.size(); ++i) {
    if (i + 1 < sorted.size() && sorted[i + 1]->name == sorted[i]->name) continue;  // the last of a name counts
    text += text.size() == 1 ? "\n " : ",\n ";
    text += nlohmann::json(sorted[i]->name).dump() + ": ";
    append_nested(text, sorted[i]->record, 1);
  }
  if (text.size() == 1) return "{}\n";
  text += "\n}\n";
  return text;
}

}  // namespace

std::string unit_key(const Unit& unit, const UnitWords& words) {
  return words.unit + "-" + sha256_hex(unit.record.dump());
}

UnitsDone run_units(const UnitWork& work, const UnitWords& words, const Store& store, ArtifactWriter& out,
                    const std::optional<Artifact>& previous) {
  UnitsDone done = find_or_run(
      work, words, store, [](size_t) { return true; }, previous);
  out.write(records_file(words), records_text(work.units()));
  return done;
}

nlohmann::json run_shard_units(const UnitWork& work, const UnitWords& words, const Store& store, const Shard& shard) {
  return find_or_run(
             work, words, store, [&](size_t i) { return shard.owns(i); }, std::nullopt)
      .report;
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
    before = nlohmann::json::parse(store.files().read(previous->dir / records_file(words)));
  UnitsPlan plan;
  for (const auto& unit : work.units()) {
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
    const RecordChange change = diff_records(unit->record, before[unit->name], {words.members});
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
