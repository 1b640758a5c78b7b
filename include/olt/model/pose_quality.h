#pragma once
// What a pose source measured about one observation's pose: registration's fit, the laser scans it
// was interpolated between, its consistency with the fused scene. Saved in poses.json and in every
// frame record (`pose.quality`), as JSON of one of these shapes:
//   null                                   an imported trajectory (nothing measured)
//   {"key": false}                         registration: interpolated between registered observations
//   {"key": true, "first": true, ...}      registration: a sensor's first observation
//   {"key": true, "converged", "iterations", "inliers", "inlier_ratio", "rmse_m", "source_points",
//    "target_points" [, "photometric_points", "photometric_rmse"] [, "refined", "not_refined"]
//    [, "keyframe", "new_keyframe"] [, "consistency": {"fraction", "coverage", "rmse_m", "points"}]}
//   {"scan_before", "scan_after", "scan_gap_s"}                  laser poses
//   {"laser": {...the laser shape...}, "registration": {...}}    laser poses refined by registration
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "olt/core/heap_optional.h"

namespace olt {

/// What registration measured (olt/poses/registration_poses.h).
struct RegistrationQuality {
  bool key = true;     ///< registered; false: interpolated between registered observations
  bool first = false;  ///< the sensor's first observation: nothing to register against
  /// The fit, where a registration ran.
  struct Fit {
    bool converged = false;
    int iterations = 0;
    int inliers = 0;
    double inlier_ratio = 0;
    double rmse_m = 0;  ///< RMS distance of the inlier correspondences, metres
    uint64_t source_points = 0;
    uint64_t target_points = 0;
    std::optional<int> photometric_points;   ///< with the colour term
    std::optional<double> photometric_rmse;  ///< ... intensities in [0, 1]
  };
  std::optional<Fit> fit;
  std::optional<bool> refined;       ///< with a prior (laser poses' refine): whether registration moved it
  std::string not_refined;           ///< ... and why not
  std::optional<uint64_t> keyframe;  ///< memory keyframes: the keyframe the pose is chained to
  bool new_keyframe = false;         ///< ... and whether the observation became one

  /// Interpolated between registered observations (key false).
  static RegistrationQuality interpolated() {
    RegistrationQuality q;
    q.key = false;
    return q;
  }
  /// A sensor's first observation, placed by the motion model.
  static RegistrationQuality first_of_sensor() {
    RegistrationQuality q;
    q.first = true;
    return q;
  }
};

/// The laser scans a laser pose was interpolated between (olt/poses/laser_poses.h).
struct ScanQuality {
  uint64_t scan_before = 0;
  uint64_t scan_after = 0;
  double scan_gap_s = 0;  ///< seconds between them
};

/// The observation's depth against the fused scene (olt/poses/consistency.h).
struct ConsistencyQuality {
  double fraction = 0;  ///< of the points with the scene within reach, the fraction near its surface
  double coverage = 0;  ///< the fraction of points with the scene within reach
  double rmse_m = 0;    ///< their RMS distance to the surface, metres
  int points = 0;
};

/// Each part on the heap (HeapOptional): a pose without any is 24 bytes, not 232, and a run holds
/// one pose per observation.
struct PoseQuality {
  HeapOptional<RegistrationQuality> registration;
  HeapOptional<ScanQuality> laser;
  HeapOptional<ConsistencyQuality> consistency;

  bool empty() const { return !registration && !laser && !consistency; }
};

nlohmann::json to_json(const PoseQuality& q);
/// Reads any of the shapes above; throws nlohmann::json's errors on another.
PoseQuality pose_quality_from_json(const nlohmann::json& j);

}  // namespace olt
