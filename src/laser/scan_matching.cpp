#include "olt/laser/scan_matching.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <unordered_map>

#include "olt/core/parallel.h"

namespace olt {

namespace {

struct Adaptor {
  const std::vector<Eigen::Vector2d>& points;
  size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return points[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 2, uint32_t>;

}  // namespace

struct PointMap2D::Data {
  double cell_m;
  std::unordered_map<uint64_t, int> cells;
  std::vector<Eigen::Vector2d> points2, normals;
  Adaptor adaptor{points2};
  std::unique_ptr<Tree> tree;
};

PointMap2D::PointMap2D(double cell_m) : data_(std::make_unique<Data>()) { data_->cell_m = cell_m; }
PointMap2D::~PointMap2D() = default;
PointMap2D::PointMap2D(PointMap2D&&) noexcept = default;
PointMap2D& PointMap2D::operator=(PointMap2D&&) noexcept = default;
size_t PointMap2D::size() const { return data_->points2.size(); }
const std::vector<Eigen::Vector2d>& PointMap2D::points() const { return data_->points2; }
const std::vector<Eigen::Vector2d>& PointMap2D::normals() const { return data_->normals; }

void PointMap2D::add(const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& normals) {
  Data& d = *data_;
  for (size_t i = 0; i < points.size(); ++i) {
    // Cells are keyed by two 32-bit signed indices: a point beyond them is no map point.
    const double fx = std::floor(points[i].x() / d.cell_m), fy = std::floor(points[i].y() / d.cell_m);
    if (!(std::abs(fx) < 2e9 && std::abs(fy) < 2e9)) continue;
    const auto cx = static_cast<int32_t>(fx), cy = static_cast<int32_t>(fy);
    const uint64_t key = (static_cast<uint64_t>(static_cast<uint32_t>(cx)) << 32) | static_cast<uint32_t>(cy);
    if (!d.cells.emplace(key, static_cast<int>(d.points2.size())).second) continue;
    d.points2.push_back(points[i]);
    d.normals.push_back(i < normals.size() ? normals[i] : Eigen::Vector2d::Zero());
  }
  d.tree.reset();  // stale until build()
}

void PointMap2D::build() {
  data_->tree = std::make_unique<Tree>(2, data_->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
}

int PointMap2D::nearest(const Eigen::Vector2d& q, double max_d2) const {
  if (!data_->tree || data_->points2.empty()) return -1;
  uint32_t j;
  double d2;
  nanoflann::KNNResultSet<double, uint32_t> result(1);
  result.init(&j, &d2);
  data_->tree->findNeighbors(result, q.data(), nanoflann::SearchParams());
  if (result.size() == 0 || d2 > max_d2) return -1;
  return static_cast<int>(j);
}

std::vector<Eigen::Vector2d> scan_normals(const std::vector<Eigen::Vector2d>& points, double radius_m) {
  std::vector<Eigen::Vector2d> normals(points.size(), Eigen::Vector2d::Zero());
  const int n = static_cast<int>(points.size());
  for (int i = 0; i < n; ++i) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    int count = 0;
    Eigen::Vector2d near[7];
    for (int k = std::max(0, i - 3); k <= std::min(n - 1, i + 3); ++k)
      if ((points[k] - points[i]).squaredNorm() <= radius_m * radius_m) {
        near[count++] = points[k];
        mean += points[k];
      }
    if (count < 3) continue;
    mean /= count;
    Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
    for (int k = 0; k < count; ++k) C += (near[k] - mean) * (near[k] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(C);
    // On a line: the spread across it is small against the spread along it.
    if (eig.eigenvalues()(0) > 0.05 * eig.eigenvalues()(1)) continue;
    normals[i] = eig.eigenvectors().col(0).normalized();
  }
  return normals;
}

namespace {

// Derivative of R(theta) * p with respect to theta.
Eigen::Vector2d d_rotated(const Eigen::Matrix2d& R, const Eigen::Vector2d& p) {
  const Eigen::Vector2d r = R * p;
  return {-r.y(), r.x()};
}

constexpr size_t kBlock = 64;

// The Gauss-Newton normal equations of some correspondences.
struct Normal {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  int inliers = 0;
  double squared = 0;
  Normal& operator+=(const Normal& o) {
    H += o.H;
    g += o.g;
    inliers += o.inliers;
    squared += o.squared;
    return *this;
  }
};

// Point p (robot frame) at (R, t) against its nearest map point within d_max: point to line where
// the map has a normal there, point to point (at half weight: a corner or clutter pins less than a
// wall) elsewhere; Huber weights.
void accumulate(const PointMap2D& map, const Eigen::Vector2d& p, const Eigen::Matrix2d& R, const Eigen::Vector2d& t,
                double d_max, double huber_m, Normal& out) {
  const Eigen::Vector2d w = R * p + t;
  const int j = map.nearest(w, d_max * d_max);
  if (j < 0) return;
  const Eigen::Vector2d d = w - map.points()[j];
  const Eigen::Vector2d& n = map.normals()[j];
  const Eigen::Vector2d dp = d_rotated(R, p);
  ++out.inliers;
  if (n.squaredNorm() > 0) {
    const double e = n.dot(d);
    const double weight = std::abs(e) <= huber_m ? 1.0 : huber_m / std::abs(e);
    const Eigen::Vector3d J(n.x(), n.y(), n.dot(dp));
    out.H += weight * J * J.transpose();
    out.g += weight * J * e;
    out.squared += e * e;
  } else {
    const double e = d.norm();
    const double weight = 0.5 * (e <= huber_m ? 1.0 : huber_m / e);
    Eigen::Matrix<double, 2, 3> J;
    J << 1, 0, dp.x(), 0, 1, dp.y();
    out.H += weight * J.transpose() * J;
    out.g += weight * J.transpose() * d;
    out.squared += e * e;
  }
}

}  // namespace

ScanMatch match_scan(const PointMap2D& map, const std::vector<Eigen::Vector2d>& points, const Pose2& guess,
                     const ScanMatchSettings& s) {
  ScanMatch result;
  result.T_map_robot = guess;
  if (points.empty() || map.size() == 0) return result;
  double x = guess.translation().x(), y = guess.translation().y(), theta = heading(guess);
  bool last_pass = false;
  for (double d_max = s.max_correspondence_m; !last_pass; d_max = std::max(s.min_correspondence_m, d_max / 2)) {
    last_pass = d_max <= s.min_correspondence_m;
    result.converged = false;
    for (int it = 0; it < s.max_iterations; ++it) {
      ++result.iterations;
      const Eigen::Matrix2d R = Eigen::Rotation2Dd(theta).toRotationMatrix();
      const Eigen::Vector2d t(x, y);
      // Partial sums over fixed blocks, added in block order: the same bits whatever the threads do.
      const size_t blocks = (points.size() + kBlock - 1) / kBlock;
      std::vector<Normal> partial(blocks);
      parallel_for_brief(blocks, [&](size_t block) {
        for (size_t i = block * kBlock; i < std::min(points.size(), (block + 1) * kBlock); ++i)
          accumulate(map, points[i], R, t, d_max, s.huber_m, partial[block]);
      });
      Normal sum;
      for (const Normal& n : partial) sum += n;
      result.inliers = sum.inliers;
      result.inlier_ratio = static_cast<double>(sum.inliers) / static_cast<double>(points.size());
      result.rmse_m = sum.inliers > 0 ? std::sqrt(sum.squared / sum.inliers) : 0;
      if (sum.inliers < 3) break;
      const Eigen::Vector3d step = sum.H.ldlt().solve(-sum.g);
      if (!step.allFinite()) break;
      x += step(0);
      y += step(1);
      theta += step(2);
      if (step.head<2>().norm() < s.translation_eps_m && std::abs(step(2)) < s.rotation_eps_rad) {
        result.converged = true;
        break;
      }
    }
  }
  result.T_map_robot = pose2(x, y, theta);
  return result;
}

}  // namespace olt
