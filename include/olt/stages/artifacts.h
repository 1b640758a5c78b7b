#pragma once
// Typed access to the artifacts stages exchange. Files inside an artifact:
//   source:      recording.json (observations, image paths and digests) [+ generated images]
//   calibrate:   calibration.json (per-sensor intrinsics, depth range, extrinsics)
//   poses:       poses.json (T_world_sensor and validity of every observation)
//   annotations: boxes.json (native format, normalised)
//   reconstruct: scene.ply, scene.pcd, scene_preview.png, annotation_frame.json, scene_points.bin
//   propagate:   labels.json, class/…, instance/…, overlay/… per observation
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "olt/core/box.h"
#include "olt/model/recording.h"
#include "olt/stages/stage.h"

namespace olt {

/// The recording and poses a run's stages read (3.4 and 3.1 MB of JSON at 10,000 observations, ~45 ms
/// each to parse), parsed once and shared: the last of each, by the digest its artifact lists for it
/// and the artifact's folder (paths inside are made absolute against it). Owned by the run, which
/// clears it when its stages are done (10 MB at 10,000 observations).
struct SharedReads {
  template <typename T>
  struct Slot {
    std::mutex mutex;
    std::string key;
    std::shared_ptr<const T> value;
  };
  Slot<Recording> recording;
  Slot<std::vector<ObservationPose>> poses;

  void clear();
};

/// The recording of a source (image paths made absolute) and the poses of a poses stage, through the
/// run's SharedReads when the input has one (read afresh, not kept, where it has none).
std::shared_ptr<const Recording> shared_recording(const StageInput& source);
/// The files of the source's list shared_recording looks up: the recording's (its digest finds the
/// one parsed before) and those the source refers to (StageKind::looks_up of a stage that reads the
/// source only through it).
bool recording_lookup(const ListedFile& f);
std::shared_ptr<const std::vector<ObservationPose>> shared_poses(const StageInput& poses);
/// Where the labeling stage's artifact lists an observation's overlay: SENSOR/overlay/ID.jpg.
std::string overlay_file(const std::string& sensor, const std::string& observation);
/// Whether `path` is where that artifact lists an overlay.
bool is_overlay_file(std::string_view path);
/// A copy of the recording, for a stage that changes it.
Recording load_recording(const StageInput& source);
Calibration load_calibration(const StageInput& calibrate);
std::vector<Box> load_boxes(const StageInput& annotations);

/// Throws when `poses` are not those of `recording`'s observations, one per observation in order
/// (possible when a job has two sources and a stage reads poses made for the other one).
void check_poses_match(const Recording& recording, const std::vector<ObservationPose>& poses, const std::string& stage);

}  // namespace olt
