#pragma once
// A small synthetic job for tests of incremental relabelling: 12 frames of 160x120, the room's own
// boxes plus a "probe" box on a patch of floor that only the end of the camera's arc sees.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace olt::test {

/// Writes job.yaml and boxes.json into `dir` (running the job once without the probe to get the
/// room's boxes); `labels_params` is the propagate stage's params (YAML flow map). Returns the boxes.
nlohmann::json write_probe_job(const std::filesystem::path& dir, const std::string& labels_params = "{}");

/// Per frame, the ids of the boxes its frame record lists (those whose rays it sees).
std::map<std::string, std::set<std::string>> boxes_seen(const std::filesystem::path& out);

}  // namespace olt::test
