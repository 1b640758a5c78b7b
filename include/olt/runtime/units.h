#pragma once
// Work units of a job on a cluster. A stage with units (propagate: its frames) is split unit by unit:
// unit k of the recording belongs to shard k mod N. Every other stage is one unit that is never split:
// - stages that stages with units need (source, calibrate, poses, annotations) are computed by the
//   first shard that gets to them, under a lock in the shared cache; the others wait and reuse it;
// - stages that need no frames and feed none (reconstruct) go to one shard each, in turn;
// - stages that need the frames (export, report) run in `olt merge`.
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "olt/job/job.h"
#include "olt/runtime/environment.h"

namespace olt {

enum class StageRole { before_frames, frames, after_frames, independent };

/// Each stage's role, by id, from the kinds and the `needs` graph.
std::map<std::string, StageRole> stage_roles(const Job& job, const Environment& env = {});

/// For an independent stage: the shard that runs it, of `count` (`roles` from stage_roles).
int owner_shard(const Job& job, const std::map<std::string, StageRole>& roles, const std::string& stage_id, int count);

/// `olt plan --units --json`: {"job", "shards", "units": [{"unit", "stage", "kind", "scope":
/// "sequence"|"frame"|"merge", "shard": i | "any" | "merge", "observation"?, "sensor"?}]}, in a
/// fixed order: the job's stage order, frames in the recording's order. Frames are listed when the
/// recording's source can be read (it is run aside when not cached).
nlohmann::json plan_units(const Job& job, int shards);

}  // namespace olt
