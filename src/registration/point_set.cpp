#include "olt/registration/point_set.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <unordered_map>

#include "olt/core/parallel.h"
#include "olt/core/voxel.h"

namespace olt {
namespace {

struct Adaptor {
  const std::vector<Eigen::Vector3d>& points;
  size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return points[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3, uint32_t>;

}  // namespace

struct KdTree::Index {
  Adaptor adaptor;
  Tree tree;
  explicit Index(const std::vector<Eigen::Vector3d>& points)
      : adaptor{points}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

KdTree::KdTree(const std::vector<Eigen::Vector3d>& points) : index_(std::make_unique<Index>(points)) {}
KdTree::~KdTree() = default;

size_t KdTree::knn(const Eigen::Vector3d& query, size_t k, uint32_t* indices, double* squared_distances) const {
  if (index_->adaptor.points.empty()) return 0;
  return index_->tree.knnSearch(query.data(), k, indices, squared_distances);
}

std::vector<Eigen::Vector3d> voxel_downsample(const std::vector<Eigen::Vector3d>& points, double voxel_size_m) {
  struct Sum {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
  };
  std::unordered_map<uint64_t, Sum> voxels;
  voxels.reserve(points.size() / 4);
  for (const auto& p : points) {
    Sum& s = voxels[voxel_key(p, voxel_size_m)];
    s.sum += p;
    ++s.n;
  }
  std::vector<std::pair<uint64_t, Eigen::Vector3d>> keyed;
  keyed.reserve(voxels.size());
  for (const auto& [key, s] : voxels) keyed.emplace_back(key, s.sum / s.n);
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3d> out;
  out.reserve(keyed.size());
  for (const auto& [key, p] : keyed) out.push_back(p);
  return out;
}

void estimate_covariances(PointSet& set, const KdTree& tree, int k, double epsilon) {
  const size_t n = set.size();
  set.covariances.assign(n, Eigen::Matrix3d::Identity());
  set.normals.assign(n, Eigen::Vector3d::UnitZ());
  parallel_for(n, [&](size_t i) {
    std::vector<uint32_t> idx(static_cast<size_t>(k));
    std::vector<double> d2(static_cast<size_t>(k));
    const size_t found = tree.knn(set.points[i], static_cast<size_t>(k), idx.data(), d2.data());
    if (found < 5) return;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (size_t j = 0; j < found; ++j) mean += set.points[idx[j]];
    mean /= static_cast<double>(found);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (size_t j = 0; j < found; ++j) {
      const Eigen::Vector3d d = set.points[idx[j]] - mean;
      cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(cov);  // eigenvalues ascending
    const Eigen::Matrix3d U = eigen.eigenvectors();
    set.covariances[i] = U * Eigen::Vector3d(epsilon, 1, 1).asDiagonal() * U.transpose();
    set.normals[i] = U.col(0);
  });
}

PointSet downsampled_point_set(const std::vector<Eigen::Vector3d>& points, double voxel_size_m,
                               int covariance_neighbors) {
  PointSet set;
  set.points = voxel_downsample(points, voxel_size_m);
  const KdTree tree(set.points);
  estimate_covariances(set, tree, covariance_neighbors);
  return set;
}

PointSet transformed(const PointSet& set, const Pose& T) {
  PointSet out;
  const Eigen::Matrix3d R = T.linear();
  out.points.reserve(set.size());
  for (const auto& p : set.points) out.points.push_back(T * p);
  for (const auto& c : set.covariances) out.covariances.push_back(R * c * R.transpose());
  for (const auto& n : set.normals) out.normals.push_back(R * n);
  return out;
}

}  // namespace olt
