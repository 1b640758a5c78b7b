#include "olt/registration/registration.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

#include "olt/core/parallel.h"
#include "olt/registration/photometric.h"

namespace olt {
namespace {

struct Linearization {
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  double squared_error = 0;        ///< geometric, metres squared
  int inliers = 0;                 ///< geometric correspondences
  double photometric_squared = 0;  ///< colour residuals, intensity squared
  int photometric_points = 0;      ///< colour residuals inside the target image

  void add(const Linearization& o) {
    H += o.H;
    g += o.g;
    squared_error += o.squared_error;
    inliers += o.inliers;
    photometric_squared += o.photometric_squared;
    photometric_points += o.photometric_points;
  }
};

// Sums per_point(i, sums) over i < n in parallel, as partial sums over fixed blocks added in block
// order: the result does not depend on how threads are scheduled, so a re-run gives the same bits.
template <class PerPoint>
Linearization sum_blocks(size_t n, PerPoint per_point) {
  constexpr size_t kBlock = 512;
  std::vector<Linearization> blocks((n + kBlock - 1) / kBlock);
  parallel_for(blocks.size(), [&](size_t b) {
    for (size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) per_point(i, blocks[b]);
  });
  Linearization total;
  for (const auto& b : blocks) total.add(b);
  return total;
}

// One Gauss-Newton linearisation at T over all correspondences. With the left perturbation
// T <- Exp(xi) T, xi = (omega, v), the residual d = q - T p has Jacobian [ [Tp]x, -I ].
Linearization linearize(const PointSet& target, const KdTree& tree, const PointSet& source, const Pose& T,
                        const RegistrationSetting& s) {
  const bool gicp = s.method == RegistrationMethod::gicp;
  const double max_d2 = s.max_correspondence_m * s.max_correspondence_m;
  const Eigen::Matrix3d R = T.linear();
  return sum_blocks(source.size(), [&](size_t i, Linearization& local) {
    const Eigen::Vector3d Tp = T * source.points[i];
    uint32_t j;
    double d2;
    if (tree.knn(Tp, 1, &j, &d2) == 0 || d2 > max_d2) return;
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
  });
}

// The colour term at T: r = I_target(pi(T_color_world T p)) - I_source(p), Jacobian
// grad(I) * d pi / d q * R_color_world * [ -[Tp]x, I ] (the same left perturbation).
Linearization linearize_photometric(const PhotometricTerm& c, const Pose& T) {
  const PhotometricPoints& source = *c.source;
  const IntensityImage& image = *c.target;
  const Eigen::Matrix3d R_cw = c.T_color_world.linear();
  return sum_blocks(source.points.size(), [&](size_t i, Linearization& local) {
    const Eigen::Vector3d q = T * source.points[i];
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J_uv;
    float intensity, gx, gy;
    if (!image.pixel(c.T_color_world * q, &uv, &J_uv) || !sample(image.intensity, uv, &intensity) ||
        !sample(image.gradient_x, uv, &gx) || !sample(image.gradient_y, uv, &gy))
      return;
    const double r = intensity - source.intensities[i];
    const Eigen::RowVector3d J_q = Eigen::RowVector2d(gx, gy) * J_uv * R_cw;
    Eigen::Matrix<double, 1, 6> J;
    J.leftCols<3>() = -J_q * skew(q);
    J.rightCols<3>() = J_q;
    const double w = c.weight * (std::abs(r) <= c.huber ? 1 : c.huber / std::abs(r));
    local.H += w * J.transpose() * J;
    local.g += w * J.transpose() * r;
    local.photometric_squared += r * r;
    ++local.photometric_points;
  });
}

Linearization linearize_all(const PointSet& target, const KdTree& tree, const PointSet& source, const Pose& T,
                            const RegistrationSetting& s, const PhotometricTerm* photometric) {
  Linearization lin = linearize(target, tree, source, T, s);
  if (photometric && photometric->weight > 0) lin.add(linearize_photometric(*photometric, T));
  return lin;
}

}  // namespace

RegistrationResult register_point_sets(const PointSet& target, const KdTree& tree, const PointSet& source,
                                       const Pose& guess, const RegistrationSetting& s,
                                       const PhotometricTerm* photometric) {
  RegistrationResult result;
  Pose T = guess;
  Linearization lin;
  for (int iteration = 1; iteration <= s.max_iterations; ++iteration) {
    lin = linearize_all(target, tree, source, T, s, photometric);
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
  T.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  lin = linearize_all(target, tree, source, T, s, photometric);
  result.T_target_source = T;
  result.inliers = lin.inliers;
  result.inlier_ratio = source.size() ? static_cast<double>(lin.inliers) / source.size() : 0;
  result.rmse_m = lin.inliers ? std::sqrt(lin.squared_error / lin.inliers) : 0;
  result.information = lin.H;
  result.photometric_points = lin.photometric_points;
  result.photometric_rmse = lin.photometric_points ? std::sqrt(lin.photometric_squared / lin.photometric_points) : 0;
  return result;
}

}  // namespace olt
