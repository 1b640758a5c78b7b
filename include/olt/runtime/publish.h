#pragma once
// Publishing stage outputs into the output folder, and OUTPUT/manifest.json:
//   {"files": [{"path", "sha256", "kind", "stage", "sensor"?, "observation"?: {"id", "timestamp"}}]}
// sorted by path. Each file is copied from its cache artifact through a temporary file and a rename;
// files the previous manifest listed and this one does not are removed; the manifest is written
// last, so it never lists a file that is not there.
#include <string>
#include <utility>
#include <vector>

#include "olt/cache/store.h"

namespace olt {

/// `artifacts`: (stage id, artifact) of every stage, in run order, on `files`. Returns the manifest.
nlohmann::json publish_outputs(const fs::path& output, const std::vector<std::pair<std::string, Artifact>>& artifacts,
                               FileSystem& files = real_file_system());

}  // namespace olt
