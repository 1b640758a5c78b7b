#include "olt/stages/stage.h"

#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "olt/formats/annotations.h"
#include "olt/stages/artifacts.h"

namespace olt {

StageKind make_stage_kind(KindSpec spec, int version, std::function<std::vector<fs::path>(const StageDecl&)> files_read,
                          StageFunction run) {
  StageKind kind;
  kind.spec = std::move(spec);
  kind.version = version;
  kind.files_read = files_read ? std::move(files_read) : [](const StageDecl&) { return std::vector<fs::path>{}; };
  kind.run = std::move(run);
  return kind;
}

const StageInput* StageContext::input(const std::string& kind) const {
  auto it = inputs.find(kind);
  return it == inputs.end() ? nullptr : &it->second;
}

const StageInput& StageContext::need(const std::string& kind) const {
  const StageInput* found = input(kind);
  if (!found) throw std::logic_error("stage '" + stage.id + "' has no input of kind " + kind);
  return *found;
}

Recording load_recording(const StageInput& source) {
  Recording r = recording_from_json(nlohmann::json::parse(read_file(source.artifact.path("recording.json"))));
  auto absolute = [&](std::string& path) {
    if (!path.empty() && fs::path(path).is_relative()) path = source.artifact.path(path).string();
  };
  for (auto& o : r.observations) {
    absolute(o.depth.path);
    if (o.color) absolute(o.color->path);
  }
  absolute(r.groundtruth);
  absolute(r.boxes);
  absolute(r.laser_scans);
  absolute(r.odometry);
  return r;
}

Calibration load_calibration(const StageInput& calibrate) {
  Calibration c;
  const auto j = nlohmann::json::parse(read_file(calibrate.artifact.path("calibration.json")));
  for (const auto& [sensor, value] : j.items()) c[sensor] = calibration_from_json(value);
  return c;
}

std::vector<ObservationPose> load_poses(const StageInput& poses) {
  return poses_from_json(nlohmann::json::parse(read_file(poses.artifact.path("poses.json"))));
}

void check_poses_match(const Recording& recording, const std::vector<ObservationPose>& poses,
                       const std::string& stage) {
  bool match = poses.size() == recording.observations.size();
  for (size_t i = 0; match && i < poses.size(); ++i) match = poses[i].observation == recording.observations[i].id;
  if (!match)
    throw std::runtime_error("stage '" + stage +
                             "': its poses do not belong to the recording it reads; name the "
                             "poses stage of that recording in needs");
}

std::vector<Box> load_boxes(const StageInput& annotations) {
  // Written by the annotations stage from boxes it validated: read as trusted.
  return read_native_annotations(read_file(annotations.artifact.path("boxes.json")));
}

}  // namespace olt
