#pragma once
// The 2D laser map (paper Sec. III-B) and localization in it.
// Mapping: each scan is matched against the recent keyframes, starting from the previous pose moved
// by the odometry increment; a scan taken after the robot moved or turned enough since the last
// keyframe becomes one. Keyframes that come back to a place seen long before are matched against
// it (loop closure), and a pose graph over all keyframes (the tracked increments and the loop
// matches) is optimised; every scan's pose follows its keyframe, and the map is all keyframes'
// points at their optimised poses. The robot at the first scan is the map's origin.
// Localization: the same matching against a fixed map, from a given start pose.
#include <string>
#include <vector>

#include "olt/laser/scan_matching.h"
#include "olt/model/laser.h"

namespace olt {

struct LaserMapSettings {
  ScanMatchSettings matching;
  double min_range_m = 0.1;       ///< nearer returns are ignored (the robot itself), metres
  double max_range_m = 30;        ///< farther returns are ignored (sparse, noisy), metres
  double key_distance_m = 0.3;    ///< a scan joins the map after the robot moved this far ...
  double key_angle_deg = 10;      ///< ... or turned this much since the last keyframe
  double map_cell_m = 0.05;       ///< the map keeps one point per cell of this size, metres
  int local_keyframes = 20;       ///< tracking matches against this many recent keyframes
  double max_rmse_m = 0.1;        ///< a match with a larger point-to-line RMSE fails, metres
  double min_inlier_ratio = 0.3;  ///< a match with fewer inliers than this fraction fails
  /// Loop closure: a keyframe is matched against earlier keyframes within this distance that are
  /// at least `loop_min_keyframes` keyframes back; accepted matches join a pose graph optimised
  /// over all keyframes (0 = no loop closure), metres.
  double loop_radius_m = 3.0;
  int loop_min_keyframes = 20;
  double loop_min_inlier_ratio = 0.6;  ///< a loop match needs this many inliers ...
  double loop_max_rmse_m = 0.05;       ///< ... and at most this RMSE
};

/// The robot's pose when a scan was taken, with how the scan matched.
struct ScanPose {
  double timestamp = 0;
  Pose2 T_map_robot = Pose2::Identity();
  ScanMatch match;
  bool key = false;   ///< the scan joined the map
  bool valid = true;  ///< false: the match failed and the pose is the odometry's guess
  std::string flag;   ///< why not valid
};

struct LaserMap {
  PointMap2D map;
  std::vector<ScanPose> poses;  ///< one per scan, in order
  int loop_closures = 0;        ///< loop matches accepted into the pose graph
};

LaserMap build_laser_map(const std::vector<LaserScan>& scans, const std::vector<OdometrySample>& odometry,
                         const LaserMapSettings& settings);

std::vector<ScanPose> localize_scans(const PointMap2D& map, const std::vector<LaserScan>& scans,
                                     const std::vector<OdometrySample>& odometry, const LaserMapSettings& settings,
                                     const Pose2& T_map_robot_first = Pose2::Identity());

}  // namespace olt
