#pragma once
// How well an observation agrees with the scene the poses make: its depth points placed by its pose,
// compared with the scene's surface. A pose that is off puts its points in front of or behind the
// surfaces the other observations agree on; a good one puts nearly all of them on it.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "olt/core/geometry.h"

namespace olt {

struct ConsistencySetting {
  double distance_m = 0.03;   ///< a point within this distance of the surface (along its normal) agrees, metres
  double reach_m = 0.1;       ///< a point with no scene point this close sees what the scene lacks (not scored), metres
  double min_fraction = 0.6;  ///< observations whose agreeing fraction is lower are flagged
};

struct Consistency {
  int points = 0;       ///< the observation's points compared
  double coverage = 0;  ///< the fraction of them with the scene within reach_m (the rest see what it lacks)
  double fraction = 0;  ///< of those, the fraction within distance_m of the surface
  double rmse_m = 0;    ///< their RMS distance to the surface, metres
};

/// The scene's surface: points with unit normals (world frame), searchable.
class SceneSurface {
 public:
  SceneSurface(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals);
  ~SceneSurface();
  SceneSurface(const SceneSurface&) = delete;
  SceneSurface& operator=(const SceneSurface&) = delete;

  /// `points_sensor` placed by `T_world_sensor` and scored against the surface.
  Consistency score(const std::vector<Eigen::Vector3d>& points_sensor, const Pose& T_world_sensor,
                    const ConsistencySetting& setting) const;
  size_t size() const { return points_.size(); }

 private:
  std::vector<Eigen::Vector3d> points_, normals_;
  struct Index;
  std::unique_ptr<Index> index_;
};

}  // namespace olt
