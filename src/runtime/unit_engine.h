#pragma once
// The runtime's side of stages that work in units (frames): each unit is keyed by the hash of its
// record, found in the cache or run into an entry of its own, shared across shards, and explained
// in `olt plan` by the same comparison as stages (explain.h). Private to the runtime.
#include <atomic>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "olt/cache/store.h"
#include "olt/runtime/shard.h"
#include "olt/stages/stage.h"

namespace olt {

/// A unit's cache key: the hash of its record, after its kind ("frame-…").
std::string unit_key(const Unit& unit, const UnitWords& words);

/// Every unit found in the cache or run (in parallel), each entry taken into the stage's artifact as
/// it comes (UnitWork::take); the units' records are written into the stage's artifact (`<unit>s.json`,
/// frames.json) for the next `olt plan` to compare with. Returns what this run reused and ran, for the log.
/// Once `stop` is set, no unit starts running: those under way finish into the cache, then
/// RunStopped says how many are left. In a process that keeps memory (`olt watch`), the units' entries
/// are kept under `kept_name` (when given), and the store forgets those of the run before no unit
/// uses now (Store::forget_unused): an edit's frames made again each cycle are not remembered for good.
nlohmann::json run_units(UnitWork& work, const UnitWords& words, const Store& store, ArtifactWriter& out,
                         const std::atomic<bool>* stop = nullptr, const std::string& kept_name = {});

/// A shard's units only (positions index, index + count, ...), run into the cache where missing;
/// `stop` as for run_units.
nlohmann::json run_shard_units(const UnitWork& work, const UnitWords& words, const Store& store, const Shard& shard,
                               const std::atomic<bool>* stop = nullptr);

/// For `olt merge`: throws ShardsIncomplete naming the units no shard left in the cache.
void check_units_cached(const UnitWork& work, const UnitWords& words, const Store& store, const std::string& stage_id,
                        int shards);

/// For `olt plan`: how many units would run and how many be reused, and why they run, against the
/// records the stage's previous artifact holds (`<unit>s.json`).
nlohmann::json explain_units(const UnitWork& work, const UnitWords& words, const Store& store,
                             const std::optional<Artifact>& previous);

}  // namespace olt
