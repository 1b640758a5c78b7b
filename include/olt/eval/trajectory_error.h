#pragma once
// Trajectory error as the TUM RGB-D benchmark defines it (Sturm et al., IROS 2012, Sec. VI):
//   ATE: estimate and ground truth associated by timestamp, the estimate aligned to the ground
//        truth by the least-squares rigid transform (Umeyama, no scale), RMSE of the translation
//        differences (and, beside TUM's definition, of the rotation differences);
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
  int matched = 0;                                 ///< associated pose pairs
  ErrorStats ate_m;                                ///< absolute trajectory error, metres
  ErrorStats ate_deg;  ///< rotation between the aligned estimate and the ground truth, degrees (heading for a robot)
  ErrorStats rpe_frame_m, rpe_frame_deg;           ///< relative error between consecutive matched poses
  ErrorStats rpe_second_m, rpe_second_deg;         ///< relative error over 1 s ("drift")
  Pose T_groundtruth_estimate = Pose::Identity();  ///< the ATE alignment
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
