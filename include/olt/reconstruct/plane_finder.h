#pragma once
// PCL's RANSAC plane fit (libpcl-sample-consensus), reached through this table like the cloud
// writers (olt/formats/cloud_writer.h): the `olt` binary loads it on first use from the clouds
// module; tests link it directly.
#include <Eigen/Core>
#include <vector>

namespace olt {

/// A plane n·p + d = 0 (n unit length) and how many of the points lie on it.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double d = 0;
  size_t inliers = 0;
};

/// What is asked of the RANSAC: planes whose normal is within `max_angle_rad` of `axis`
/// (`perpendicular`: planes perpendicular to the axis, e.g. floors for axis "up"), or whose
/// normal is perpendicular to it within that angle (walls); 90 degrees or more: planes of any
/// orientation. Points within `distance_m` count.
struct PlaneQuery {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  bool perpendicular = true;
  double max_angle_rad = 0.5;
  double distance_m = 0.02;
  int max_planes = 4;  ///< each found on the points the planes before left
  size_t min_inliers = 100;
};

struct PlaneFinder {
  /// Up to `max_planes` planes, each with at least `min_inliers` points, in the order found (the
  /// largest first); coefficients refined by least squares over the inliers. Deterministic.
  void (*find)(const std::vector<Eigen::Vector3f>& points, const PlaneQuery& query, std::vector<Plane>& planes);
};

/// The table; throws std::runtime_error naming the module when it cannot be loaded.
const PlaneFinder& plane_finder();

}  // namespace olt
