#pragma once
// 2D scan matching: a scan's points (robot frame) aligned to a point map by ICP, point-to-line
// where the map is locally straight (walls) and point-to-point elsewhere, Gauss-Newton on
// (x, y, heading) with Huber weights, over passes of shrinking correspondence distance so that a
// guess off by a metre still converges.
#include <memory>
#include <vector>

#include "olt/model/laser.h"

namespace olt {

struct ScanMatchSettings {
  double max_correspondence_m = 1.0;  ///< first pass: farthest correspondence, metres
  double min_correspondence_m = 0.1;  ///< last pass (halving from the first), metres
  int max_iterations = 20;            ///< Gauss-Newton iterations per pass
  double huber_m = 0.03;              ///< residuals beyond this are down-weighted, metres
  double translation_eps_m = 1e-4;    ///< converged when a step moves less ...
  double rotation_eps_rad = 1e-5;     ///< ... and turns less than this
};

struct ScanMatch {
  Pose2 T_map_robot = Pose2::Identity();
  bool converged = false;
  int iterations = 0;       ///< over all passes
  int inliers = 0;          ///< points with a correspondence in the last pass
  double inlier_ratio = 0;  ///< inliers / points
  double rmse_m = 0;        ///< of the inliers' point-to-line (or point) distances
};

/// Map points with normals, thinned to one point per cell; query with match_scan after build().
class PointMap2D {
 public:
  explicit PointMap2D(double cell_m = 0.05);
  ~PointMap2D();
  PointMap2D(PointMap2D&&) noexcept;
  PointMap2D& operator=(PointMap2D&&) noexcept;

  /// Adds points (map frame) with their normals (zero where a point has none); a point whose cell
  /// already holds one is dropped.
  void add(const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& normals);
  void build();  ///< the search index over everything added so far
  size_t size() const;
  const std::vector<Eigen::Vector2d>& points() const;
  const std::vector<Eigen::Vector2d>& normals() const;

  /// Nearest point within sqrt(max_d2) of q; -1 when none (or before build()).
  int nearest(const Eigen::Vector2d& q, double max_d2) const;

 private:
  struct Data;  // on the heap, so that the index's reference to the points survives moves
  std::unique_ptr<Data> data_;
};

/// Normals of a scan's points (ordered by ray) from the points within `radius_m` among the 3 rays
/// on each side, where they lie on a line; zero elsewhere (corners, clutter, isolated returns).
std::vector<Eigen::Vector2d> scan_normals(const std::vector<Eigen::Vector2d>& points, double radius_m = 0.25);

ScanMatch match_scan(const PointMap2D& map, const std::vector<Eigen::Vector2d>& points_robot, const Pose2& guess,
                     const ScanMatchSettings& settings);

}  // namespace olt
