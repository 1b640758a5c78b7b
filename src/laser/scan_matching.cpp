#include "olt/laser/scan_matching.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "olt/registration/point_set.h"

namespace olt {

struct PointMap2D::Data {
  double cell_m;
  std::unordered_map<int64_t, int> cells;
  std::vector<Eigen::Vector3d> points;  // z = 0: the search index is the registration's k-d tree
  std::vector<Eigen::Vector2d> points2, normals;
  std::unique_ptr<KdTree> tree;
};

PointMap2D::PointMap2D(double cell_m) : data_(std::make_unique<Data>()) { data_->cell_m = cell_m; }
PointMap2D::~PointMap2D() = default;
PointMap2D::PointMap2D(PointMap2D&&) noexcept = default;
PointMap2D& PointMap2D::operator=(PointMap2D&&) noexcept = default;
size_t PointMap2D::size() const { return data_->points.size(); }
const std::vector<Eigen::Vector2d>& PointMap2D::points() const { return data_->points2; }
const std::vector<Eigen::Vector2d>& PointMap2D::normals() const { return data_->normals; }

void PointMap2D::add(const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& normals) {
  Data& d = *data_;
  for (size_t i = 0; i < points.size(); ++i) {
    const int64_t cx = static_cast<int64_t>(std::floor(points[i].x() / d.cell_m));
    const int64_t cy = static_cast<int64_t>(std::floor(points[i].y() / d.cell_m));
    const int64_t key = (cx << 32) ^ (cy & 0xffffffff);
    if (!d.cells.emplace(key, static_cast<int>(d.points.size())).second) continue;
    d.points.emplace_back(points[i].x(), points[i].y(), 0.0);
    d.points2.push_back(points[i]);
    d.normals.push_back(i < normals.size() ? normals[i] : Eigen::Vector2d::Zero());
  }
  d.tree.reset();  // stale until build()
}

void PointMap2D::build() { data_->tree = std::make_unique<KdTree>(data_->points); }

int PointMap2D::nearest(const Eigen::Vector2d& q, double max_d2) const {
  if (!data_->tree || data_->points.empty()) return -1;
  uint32_t j;
  double d2;
  if (data_->tree->knn(Eigen::Vector3d(q.x(), q.y(), 0), 1, &j, &d2) == 0 || d2 > max_d2) return -1;
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
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      Eigen::Vector3d g = Eigen::Vector3d::Zero();
      int inliers = 0;
      double squared = 0;
      for (const auto& p : points) {
        const Eigen::Vector2d w = R * p + t;
        const int j = map.nearest(w, d_max * d_max);
        if (j < 0) continue;
        const Eigen::Vector2d d = w - map.points()[j];
        const Eigen::Vector2d& n = map.normals()[j];
        const Eigen::Vector2d dp = d_rotated(R, p);
        ++inliers;
        if (n.squaredNorm() > 0) {  // point to line
          const double e = n.dot(d);
          const double weight = std::abs(e) <= s.huber_m ? 1.0 : s.huber_m / std::abs(e);
          const Eigen::Vector3d J(n.x(), n.y(), n.dot(dp));
          H += weight * J * J.transpose();
          g += weight * J * e;
          squared += e * e;
        } else {  // point to point, at half weight: a corner or clutter pins less than a wall
          const double e = d.norm();
          const double weight = 0.5 * (e <= s.huber_m ? 1.0 : s.huber_m / e);
          Eigen::Matrix<double, 2, 3> J;
          J << 1, 0, dp.x(), 0, 1, dp.y();
          H += weight * J.transpose() * J;
          g += weight * J.transpose() * d;
          squared += e * e;
        }
      }
      result.inliers = inliers;
      result.inlier_ratio = static_cast<double>(inliers) / static_cast<double>(points.size());
      result.rmse_m = inliers > 0 ? std::sqrt(squared / inliers) : 0;
      if (inliers < 3) break;
      const Eigen::Vector3d step = H.ldlt().solve(-g);
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
