#include "olt/registration/registration.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

namespace olt {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

struct Linearization {
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  double squared_error = 0;
  int inliers = 0;
};

// One Gauss-Newton linearisation at T over all correspondences. With the left perturbation
// T <- Exp(xi) T, xi = (omega, v), the residual d = q - T p has Jacobian [ [Tp]x, -I ].
Linearization linearize(const PointSet& target, const KdTree& tree, const PointSet& source, const Pose& T,
                        const RegistrationSetting& s) {
  const bool gicp = s.method == "gicp";
  const double max_d2 = s.max_correspondence_m * s.max_correspondence_m;
  const Eigen::Matrix3d R = T.linear();
  // Partial sums over fixed blocks, added in block order: the result does not depend on how
  // threads are scheduled, so a re-run gives the same bits.
  constexpr size_t kBlock = 512;
  std::vector<Linearization> blocks((source.size() + kBlock - 1) / kBlock);
#pragma omp parallel for schedule(static)
  for (size_t b = 0; b < blocks.size(); ++b) {
    Linearization& local = blocks[b];
    for (size_t i = b * kBlock; i < std::min(source.size(), (b + 1) * kBlock); ++i) {
      const Eigen::Vector3d Tp = T * source.points[i];
      uint32_t j;
      double d2;
      if (tree.knn(Tp, 1, &j, &d2) == 0 || d2 > max_d2) continue;
      const Eigen::Vector3d d = target.points[j] - Tp;
      Eigen::Matrix<double, 3, 6> J;
      J.leftCols<3>() = skew(Tp);
      J.rightCols<3>() = -Eigen::Matrix3d::Identity();
      if (gicp) {
        // Eq. (2) of the GICP paper: Mahalanobis distance with C_target + R C_source R^T.
        const Eigen::Matrix3d W = (target.covariances[j] + R * source.covariances[i] * R.transpose()).inverse();
        local.H += J.transpose() * W * J;
        local.g += J.transpose() * W * d;
      } else {
        const Eigen::Vector3d& n = target.normals[j];
        const Eigen::Matrix<double, 1, 6> Jn = n.transpose() * J;
        local.H += Jn.transpose() * Jn;
        local.g += Jn.transpose() * n.dot(d);
      }
      local.squared_error += d2;
      ++local.inliers;
    }
  }
  Linearization total;
  for (const auto& b : blocks) {
    total.H += b.H;
    total.g += b.g;
    total.squared_error += b.squared_error;
    total.inliers += b.inliers;
  }
  return total;
}

}  // namespace

RegistrationResult register_point_sets(const PointSet& target, const KdTree& tree, const PointSet& source,
                                       const Pose& guess, const RegistrationSetting& s) {
  RegistrationResult result;
  Pose T = guess;
  Linearization lin;
  for (int iteration = 1; iteration <= s.max_iterations; ++iteration) {
    lin = linearize(target, tree, source, T, s);
    result.iterations = iteration;
    if (lin.inliers < 6) break;
    const Eigen::Matrix<double, 6, 1> xi = lin.H.ldlt().solve(-lin.g);
    if (!xi.allFinite()) break;
    Pose update = Pose::Identity();
    const Eigen::Vector3d omega = xi.head<3>();
    if (omega.norm() > 0) update.linear() = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
    update.translation() = xi.tail<3>();
    T = update * T;
    if (xi.tail<3>().norm() < s.translation_eps_m && omega.norm() < s.rotation_eps_rad) {
      result.converged = true;
      break;
    }
  }
  lin = linearize(target, tree, source, T, s);
  result.T_target_source = T;
  result.inliers = lin.inliers;
  result.inlier_ratio = source.size() ? static_cast<double>(lin.inliers) / source.size() : 0;
  result.rmse_m = lin.inliers ? std::sqrt(lin.squared_error / lin.inliers) : 0;
  return result;
}

}  // namespace olt
