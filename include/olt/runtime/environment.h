#pragma once
// What a run uses besides its job: a file system and the stage kinds it knows. `olt` uses the
// machine's file system and OLT's kinds; the runtime's tests use a memory file system and kinds of
// their own, so incremental runs, shards, publishing and faults are tested in memory and fast.
#include <string>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/stages/stage.h"

namespace olt {

struct Environment {
  FileSystem* files = &real_file_system();
  const std::vector<StageKind>* kinds = &stage_kinds();

  /// The kind named `name` (the job was validated against the same kinds).
  const StageKind& kind(const std::string& name) const;
};

}  // namespace olt
