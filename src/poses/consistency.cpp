#include "olt/poses/consistency.h"

#include <cmath>

#include "olt/registration/point_set.h"

namespace olt {

struct SceneSurface::Index {
  KdTree tree;
  explicit Index(const std::vector<Eigen::Vector3d>& points) : tree(points) {}
};

SceneSurface::SceneSurface(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals)
    : points_(std::move(points)), normals_(std::move(normals)), index_(std::make_unique<Index>(points_)) {}

SceneSurface::~SceneSurface() = default;

Consistency SceneSurface::score(const std::vector<Eigen::Vector3d>& points_sensor, const Pose& T_world_sensor,
                                const ConsistencySetting& s) const {
  Consistency c;
  int agreeing = 0, reached = 0;
  double squared = 0;
  for (const auto& p : points_sensor) {
    const Eigen::Vector3d q = T_world_sensor * p;
    uint32_t j;
    double d2;
    ++c.points;
    if (index_->tree.knn(q, 1, &j, &d2) == 0 || d2 > s.reach_m * s.reach_m) continue;
    // Point-to-plane: along the surface the scene's points are a voxel apart, across it they are exact.
    const double d = std::abs(normals_[j].dot(q - points_[j]));
    ++reached;
    squared += d * d;
    if (d <= s.distance_m) ++agreeing;
  }
  // Points that see what the scene lacks (a view no keyframe had) say nothing either way; those
  // near it say whether the pose puts them on it.
  c.coverage = c.points ? static_cast<double>(reached) / c.points : 0;
  c.fraction = reached ? static_cast<double>(agreeing) / reached : 0;
  c.rmse_m = reached ? std::sqrt(squared / reached) : 0;
  return c;
}

}  // namespace olt
