#pragma once
// Point sets for registration: positions with per-point covariances and normals, voxel
// downsampling, and k-nearest-neighbour search (nanoflann k-d tree behind a small interface).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "olt/core/geometry.h"

namespace olt {

struct PointSet {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Matrix3d> covariances;  ///< regularised (GICP "plane" form), empty until estimated
  std::vector<Eigen::Vector3d> normals;      ///< unit, empty until estimated

  size_t size() const { return points.size(); }
};

/// One point per occupied voxel: the centroid of the points that fell into it, in voxel order.
std::vector<Eigen::Vector3d> voxel_downsample(const std::vector<Eigen::Vector3d>& points, double voxel_size_m);

class KdTree {
 public:
  explicit KdTree(const std::vector<Eigen::Vector3d>& points);  ///< keeps a reference: points must outlive it
  ~KdTree();
  KdTree(const KdTree&) = delete;
  KdTree& operator=(const KdTree&) = delete;
  /// Indices and squared distances of the k nearest points (fewer when the set is smaller).
  size_t knn(const Eigen::Vector3d& query, size_t k, uint32_t* indices, double* squared_distances) const;

 private:
  struct Index;
  std::unique_ptr<Index> index_;
};

/// Covariance of each point's k nearest neighbours, regularised as in Generalized-ICP (Segal et
/// al. 2009, Sec. III-B): eigenvalues replaced by (1, 1, epsilon) so every point is a small plane
/// patch; the normal is the eigenvector of the smallest eigenvalue.
void estimate_covariances(PointSet& set, const KdTree& tree, int k, double epsilon = 1e-3);

/// `points` downsampled to `voxel_size_m` voxels, with the covariances and normals of each point's
/// `covariance_neighbors` nearest neighbours: a registration source or target.
PointSet downsampled_point_set(const std::vector<Eigen::Vector3d>& points, double voxel_size_m,
                               int covariance_neighbors);

/// The set moved by `T` (points, covariances and normals).
PointSet transformed(const PointSet& set, const Pose& T);

}  // namespace olt
