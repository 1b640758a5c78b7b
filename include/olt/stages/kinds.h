#pragma once
// One function per stage kind, each defined in src/stages/<kind>_stage.cpp.
#include "olt/stages/stage.h"

namespace olt {

StageKind source_kind();
StageKind calibrate_kind();
StageKind laser_map_kind();
StageKind poses_kind();
StageKind reconstruct_kind();
StageKind annotations_kind();
StageKind propagate_kind();
StageKind export_kind();
StageKind report_kind();

}  // namespace olt
