#pragma once
// The annotation frame: the scene levelled for drawing boxes. z is up (the normal of the dominant
// horizontal support planes, floor and table tops, found by RANSAC; or given), the origin lies on the
// lowest of them (the floor where it is seen) under the scene's centre, and x runs along the
// largest wall (or the scene's main horizontal extent). Boxes drawn yaw-only in it fit objects
// standing on the floor, whatever the tilt of the poses' frame (a motion-capture or first-camera frame).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "olt/core/geometry.h"
#include "olt/model/cloud.h"

namespace olt {

struct LevelConfig {
  bool level = true;                  ///< false: the annotation frame is the poses' frame
  std::optional<Eigen::Vector3d> up;  ///< "up" in the poses' frame, given instead of found
  double voxel_size_m = 0.01;         ///< the cloud's resolution (plane distance tolerance follows it)
};

struct AnnotationFrame {
  Pose T_world_annotation = Pose::Identity();  ///< annotation frame -> poses' (world) frame
  /// How up was decided: "support_plane", "given", "cameras" (no plane found: the cameras' mean
  /// up), or "none" (level: false).
  std::string method = "none";
  size_t support_points = 0;    ///< points on the horizontal planes that gave up
  std::string x_axis = "none";  ///< "wall", "extent" or "none"
  /// The angle between up and the poses' frame's z axis, degrees (how tilted that frame is).
  double tilt_deg() const;
};

/// The annotation frame of a scene seen from `camera_poses` (T_world_camera, optical frames: y down).
AnnotationFrame find_annotation_frame(const ColoredCloud& cloud, const std::vector<Pose>& camera_poses,
                                      const LevelConfig& config);

/// annotation_frame.json: {"T_world_annotation": [tx,ty,tz,qx,qy,qz,qw], "matrix": 4x4 rows,
/// "up_in_world", "method", "support_points", "x_axis", "tilt_deg"}.
nlohmann::json to_json(const AnnotationFrame& frame);
AnnotationFrame annotation_frame_from_json(const nlohmann::json& j);

}  // namespace olt
