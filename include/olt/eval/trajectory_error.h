#pragma once
// Trajectory error as the TUM RGB-D benchmark defines it (Sturm et al., IROS 2012, Sec. VI):
//   ATE: estimate and ground truth associated by timestamp, the estimate aligned to the ground
//        truth by the least-squares rigid transform of the positions (Umeyama, no scale), RMSE of
//        the translation differences;
//   ATE rotation (beside TUM's definition): RMSE of the angles of R_gt_k^T R_align R_est_k, after
//        the alignment that is optimal for the rotations themselves,
//        R_align = argmin_R sum_k ||R R_est_k - R_gt_k||_F^2 (H = sum_k R_gt_k R_est_k^T projected
//        onto SO(3)). The position alignment's rotation is not used for it: on a sequence that
//        barely translates (TUM fr1_rpy) the positions do not determine a rotation, and with it a
//        registration trajectory 0.68 degrees off per frame pair scored 16.5 degrees;
//   RPE: for pairs (i, j) a fixed interval apart, E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j); its translation
//        norm and rotation angle, RMSE over pairs. The interval is one frame, or one second.
// Optionally the ground truth is interpolated at the estimate's timestamps instead of associated.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "olt/model/trajectory.h"

namespace olt {

struct ErrorStats {
  double rmse = 0, mean = 0, median = 0, max = 0;
  int count = 0;
};

struct TrajectoryErrors {
  int matched = 0;     ///< associated pose pairs
  ErrorStats ate_m;    ///< absolute trajectory error, metres
  ErrorStats ate_deg;  ///< rotation between the rotation-aligned estimate and the ground truth, degrees
  ErrorStats rpe_frame_m, rpe_frame_deg;           ///< relative error between consecutive matched poses
  ErrorStats rpe_second_m, rpe_second_deg;         ///< relative error over 1 s ("drift")
  Pose T_groundtruth_estimate = Pose::Identity();  ///< the ATE alignment (of the positions)
  /// The alignment of ate_deg (of the rotations).
  Eigen::Matrix3d R_groundtruth_estimate = Eigen::Matrix3d::Identity();
};

/// Pairs of (estimate index, ground-truth index) whose timestamps differ by at most max_dt_s,
/// nearest first, each sample used once.
std::vector<std::pair<size_t, size_t>> associate_trajectories(const Trajectory& estimate, const Trajectory& truth,
                                                              double max_dt_s);

/// How ground truth is taken at an estimate's timestamp: the TUM benchmark's nearest sample
/// (`associate_trajectories`), or interpolated between the two samples around it, which removes
/// the sampling offset (up to 5 ms at 100 Hz, 0.4 deg at 80 deg/s) from the errors.
enum class GroundTruthTiming { nearest, interpolated };

/// Estimates without ground truth within max_dt_s are left out (`matched` counts the rest).
TrajectoryErrors trajectory_errors(const Trajectory& estimate, const Trajectory& truth, double max_dt_s,
                                   GroundTruthTiming timing = GroundTruthTiming::nearest);

ErrorStats stats_of(std::vector<double> values);

/// Top view (x-y) of both trajectories, ground truth green (when given), the aligned estimate red.
cv::Mat plot_trajectories(const Trajectory& estimate, const Trajectory& truth, const Pose& T_groundtruth_estimate,
                          int size_px, const std::string& estimate_name = "estimate (aligned)");

}  // namespace olt
