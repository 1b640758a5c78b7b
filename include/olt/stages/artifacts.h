#pragma once
// Typed access to the artifacts stages exchange. Files inside an artifact:
//   source:      recording.json (observations, image paths and digests) [+ generated images]
//   calibrate:   calibration.json (per-sensor intrinsics, depth range, extrinsics)
//   poses:       poses.json (T_world_sensor and validity of every observation)
//   annotations: boxes.json (native format, normalised)
//   reconstruct: scene.ply, scene.pcd, scene_preview.png, annotation_frame.json, scene_points.bin
//   propagate:   labels.json, class/…, instance/…, overlay/… per observation
#include <memory>
#include <vector>

#include "olt/core/box.h"
#include "olt/model/recording.h"
#include "olt/stages/stage.h"

namespace olt {

Recording load_recording(const StageInput& source);  ///< image paths made absolute
Calibration load_calibration(const StageInput& calibrate);
std::vector<ObservationPose> load_poses(const StageInput& poses);
/// The same, shared: the last recording and poses read stay in memory (one of each) until
/// forget_shared_inputs, so the stages of a run that read them again do not parse them again.
std::shared_ptr<const Recording> shared_recording(const StageInput& source);
std::shared_ptr<const std::vector<ObservationPose>> shared_poses(const StageInput& poses);
/// Lets the last recording and poses read go (a run's stages are done: 10 MB at 10,000 observations).
void forget_shared_inputs();
std::vector<Box> load_boxes(const StageInput& annotations);

/// Throws when `poses` are not those of `recording`'s observations, one per observation in order
/// (possible when a job has two sources and a stage reads poses made for the other one).
void check_poses_match(const Recording& recording, const std::vector<ObservationPose>& poses, const std::string& stage);

}  // namespace olt
