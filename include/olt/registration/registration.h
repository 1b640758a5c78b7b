#pragma once
// Rigid registration of a source point set to a target: Generalized-ICP (Segal, Haehnel, Thrun,
// RSS 2009) or point-to-plane ICP (Chen & Medioni 1992), both by Gauss-Newton on SE(3) with
// correspondences from a k-d tree, re-found every iteration.
#include <Eigen/Core>
#include <string>

#include "olt/registration/point_set.h"

namespace olt {

struct PhotometricTerm;  // olt/registration/photometric.h

enum class RegistrationMethod { gicp, icp };  ///< Generalized-ICP or point-to-plane ICP

struct RegistrationSetting {
  RegistrationMethod method = RegistrationMethod::gicp;  ///< gicp | icp (point-to-plane)
  double max_correspondence_m = 0.1;                     ///< farther nearest neighbours are not correspondences, metres
  int max_iterations = 30;                               ///< Gauss-Newton iterations at most
  double translation_eps_m = 1e-4;                       ///< converged when an update moves less than this, metres
  double rotation_eps_rad = 1e-4;                        ///< ... and turns less than this, radians
};

struct RegistrationResult {
  Pose T_target_source = Pose::Identity();
  bool converged = false;
  int iterations = 0;
  int inliers = 0;              ///< source points with a correspondence at the end
  double inlier_ratio = 0;      ///< inliers / source points
  double rmse_m = 0;            ///< RMS distance of the inlier correspondences, metres (the "fitness")
  int photometric_points = 0;   ///< colour term: source pixels seen in the target image at the end
  double photometric_rmse = 0;  ///< ... their RMS intensity difference (intensities in [0, 1])
  /// Gauss-Newton Hessian at the result, on the left perturbation T <- exp(omega, v) T in the
  /// target's frame, rotation first: the information of T_target_source (pose_graph.h's form).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};

/// `target` needs covariances (gicp) or normals (icp); `source` needs covariances for gicp. With
/// `photometric`, its colour residuals join the geometric ones in every Gauss-Newton step.
RegistrationResult register_point_sets(const PointSet& target, const KdTree& target_tree, const PointSet& source,
                                       const Pose& T_target_source_guess, const RegistrationSetting& setting,
                                       const PhotometricTerm* photometric = nullptr);

}  // namespace olt
