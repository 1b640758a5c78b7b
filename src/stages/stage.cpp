#include "olt/stages/stage.h"

#include <mutex>

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

namespace {

// The last `T` read from an artifact's file in this process, and what identifies it.
template <typename T>
struct LastRead {
  std::mutex mutex;
  std::string key;
  std::shared_ptr<const T> value;
};

template <typename T>
LastRead<T>& last_read() {
  static LastRead<T> slot;
  return slot;
}

// `file` of `artifact` as `read` makes it, or the last one read, by the file's recorded digest and the
// artifact's folder (paths inside are made absolute against it): a run's stages read the same
// recording and poses again (3.4 and 3.1 MB of JSON at 10,000 observations, ~45 ms each to parse).
// Read afresh where the artifact does not list the file.
template <typename T>
std::shared_ptr<const T> read_once(const Artifact& artifact, const std::string& file, const std::function<T()>& read) {
  LastRead<T>& last = last_read<T>();
  const ArtifactFile* listed = artifact.file(file);
  if (!listed || listed->sha256.empty()) return std::make_shared<const T>(read());
  const std::string key = listed->sha256 + "\n" + artifact.dir.string();
  {
    std::lock_guard<std::mutex> lock(last.mutex);
    if (last.value && key == last.key) return last.value;
  }
  auto value = std::make_shared<const T>(read());
  std::lock_guard<std::mutex> lock(last.mutex);
  last.key = key;
  last.value = value;
  return value;
}

template <typename T>
void forget(LastRead<T>& last) {
  std::lock_guard<std::mutex> lock(last.mutex);
  last.key.clear();
  last.value.reset();
}

}  // namespace

void forget_shared_inputs() {
  forget(last_read<Recording>());
  forget(last_read<std::vector<ObservationPose>>());
}

std::shared_ptr<const Recording> shared_recording(const StageInput& source) {
  return read_once<Recording>(source.artifact, "recording.json", [&] {
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
  });
}

Recording load_recording(const StageInput& source) { return *shared_recording(source); }

Calibration load_calibration(const StageInput& calibrate) {
  Calibration c;
  const auto j = nlohmann::json::parse(read_file(calibrate.artifact.path("calibration.json")));
  for (const auto& [sensor, value] : j.items()) c[sensor] = calibration_from_json(value);
  return c;
}

std::shared_ptr<const std::vector<ObservationPose>> shared_poses(const StageInput& poses) {
  return read_once<std::vector<ObservationPose>>(poses.artifact, "poses.json", [&] {
    return poses_from_json(nlohmann::json::parse(read_file(poses.artifact.path("poses.json"))));
  });
}

std::vector<ObservationPose> load_poses(const StageInput& poses) { return *shared_poses(poses); }

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
