#pragma once
// PCL's PCD and PLY writers (libpcl-io, with VTK behind it), reached through this table: the `olt`
// binary loads them on first use (src/modules/lazy.cpp); tests link them directly
// (src/modules/linked.cpp). cloud_files.h is what the rest of OLT calls.
#include <string>

#include "olt/model/cloud.h"

namespace olt {

struct CloudWriter {
  /// Writes `cloud` to `path`, binary PCD (`pcd`) or binary PLY; PCL's status (0: written).
  int (*colored)(const std::string& path, const ColoredCloud& cloud, bool pcd);
  int (*labeled)(const std::string& path, const LabeledCloud& cloud, bool pcd);
};

/// The writer table; throws std::runtime_error naming the module and where it was looked for when
/// it cannot be loaded.
const CloudWriter& cloud_writer();

}  // namespace olt
