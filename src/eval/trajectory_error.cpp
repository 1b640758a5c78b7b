#include "olt/eval/trajectory_error.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace olt {
namespace {

// RPE over pairs of matched samples whose time difference is closest to `interval_s` (0 = next).
void relative_errors(const std::vector<Pose>& P, const std::vector<Pose>& Q, const std::vector<double>& t,
                     double interval_s, ErrorStats* trans, ErrorStats* rot) {
  std::vector<double> dt, dr;
  for (size_t i = 0; i < P.size(); ++i) {
    size_t j = i + 1;
    if (interval_s > 0) {
      while (j < P.size() && t[j] - t[i] < interval_s) ++j;
      if (j < P.size() && j > i + 1 && std::abs(t[j - 1] - t[i] - interval_s) < std::abs(t[j] - t[i] - interval_s)) --j;
    }
    if (j >= P.size()) break;
    const Pose E = (Q[i].inverse() * Q[j]).inverse() * (P[i].inverse() * P[j]);
    dt.push_back(E.translation().norm());
    dr.push_back(rotation_angle(E) * 180.0 / M_PI);
  }
  *trans = stats_of(dt);
  *rot = stats_of(dr);
}

}  // namespace

ErrorStats stats_of(std::vector<double> v) {
  ErrorStats s;
  s.count = static_cast<int>(v.size());
  if (v.empty()) return s;
  double sum = 0, sq = 0;
  for (double x : v) {
    sum += x;
    sq += x * x;
    s.max = std::max(s.max, x);
  }
  s.mean = sum / v.size();
  s.rmse = std::sqrt(sq / v.size());
  std::sort(v.begin(), v.end());
  s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  return s;
}

std::vector<std::pair<size_t, size_t>> associate_trajectories(const Trajectory& estimate, const Trajectory& truth,
                                                              double max_dt_s) {
  std::vector<std::tuple<double, size_t, size_t>> candidates;
  for (size_t i = 0; i < estimate.size(); ++i) {
    const double t = estimate[i].timestamp;
    auto it = std::lower_bound(truth.begin(), truth.end(), t - max_dt_s,
                               [](const TrajectorySample& s, double time) { return s.timestamp < time; });
    for (; it != truth.end() && it->timestamp <= t + max_dt_s; ++it)
      candidates.emplace_back(std::abs(it->timestamp - t), i, static_cast<size_t>(it - truth.begin()));
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> used_e(estimate.size()), used_t(truth.size());
  std::vector<std::pair<size_t, size_t>> pairs;
  for (const auto& [dt, i, j] : candidates) {
    if (used_e[i] || used_t[j]) continue;
    used_e[i] = used_t[j] = true;
    pairs.emplace_back(i, j);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

TrajectoryErrors trajectory_errors(const Trajectory& estimate, const Trajectory& truth, double max_dt_s,
                                   GroundTruthTiming timing) {
  TrajectoryErrors e;
  std::vector<Pose> P, Q;
  std::vector<double> t;
  if (timing == GroundTruthTiming::nearest) {
    for (const auto& [i, j] : associate_trajectories(estimate, truth, max_dt_s)) {
      P.push_back(estimate[i].pose);
      Q.push_back(truth[j].pose);
      t.push_back(estimate[i].timestamp);
    }
  } else {
    for (const auto& s : estimate) {
      Pose q;
      double gap = 0;
      if (!interpolate_trajectory(truth, s.timestamp, &q, &gap) || gap > max_dt_s) continue;
      P.push_back(s.pose);
      Q.push_back(q);
      t.push_back(s.timestamp);
    }
  }
  e.matched = static_cast<int>(P.size());
  if (P.size() < 2) return e;
  Eigen::Matrix3Xd src(3, P.size()), dst(3, P.size());
  for (size_t k = 0; k < P.size(); ++k) {
    src.col(static_cast<Eigen::Index>(k)) = P[k].translation();
    dst.col(static_cast<Eigen::Index>(k)) = Q[k].translation();
  }
  e.T_groundtruth_estimate.matrix() = Eigen::umeyama(src, dst, false);
  e.R_groundtruth_estimate = rotation_alignment(P, Q);
  std::vector<double> ate, ate_deg;
  for (size_t k = 0; k < P.size(); ++k) {
    ate.push_back((e.T_groundtruth_estimate * P[k].translation() - Q[k].translation()).norm());
    const Eigen::Matrix3d R_error = Q[k].linear().transpose() * e.R_groundtruth_estimate * P[k].linear();
    ate_deg.push_back(Eigen::AngleAxisd(R_error).angle() * 180 / M_PI);
  }
  e.ate_m = stats_of(ate);
  e.ate_deg = stats_of(ate_deg);
  relative_errors(P, Q, t, 0, &e.rpe_frame_m, &e.rpe_frame_deg);
  relative_errors(P, Q, t, 1.0, &e.rpe_second_m, &e.rpe_second_deg);
  return e;
}

cv::Mat plot_trajectories(const Trajectory& estimate, const Trajectory& truth, const Pose& T, int size_px,
                          const std::string& estimate_name) {
  cv::Mat canvas(size_px, size_px, CV_8UC3, cv::Scalar(255, 255, 255));
  std::vector<Eigen::Vector2d> a, b;
  for (const auto& s : truth) a.push_back(s.pose.translation().head<2>());
  for (const auto& s : estimate) b.push_back((T * s.pose.translation()).head<2>());
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (const auto* list : {&a, &b})
    for (const auto& p : *list) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  if (a.empty() && b.empty()) return canvas;
  const double extent = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-3});
  const double scale = 0.9 * size_px / extent, margin = 0.05 * size_px;
  auto pixel = [&](const Eigen::Vector2d& p) {
    return cv::Point2d(margin + (p.x() - lo.x()) * scale, size_px - margin - (p.y() - lo.y()) * scale);
  };
  auto draw = [&](const std::vector<Eigen::Vector2d>& points, const cv::Scalar& color) {
    for (size_t i = 1; i < points.size(); ++i)
      cv::line(canvas, pixel(points[i - 1]), pixel(points[i]), color, 2, cv::LINE_AA);
  };
  draw(a, {40, 160, 40});
  draw(b, {40, 40, 220});
  if (!truth.empty())
    cv::putText(canvas, "ground truth", {10, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, {40, 160, 40}, 1, cv::LINE_AA);
  cv::putText(canvas, estimate_name, {10, 40}, cv::FONT_HERSHEY_SIMPLEX, 0.5, {40, 40, 220}, 1, cv::LINE_AA);
  char scale_text[64];
  std::snprintf(scale_text, sizeof(scale_text), "top view, %.3f m across", extent);
  cv::putText(canvas, scale_text, {10, 60}, cv::FONT_HERSHEY_SIMPLEX, 0.5, {80, 80, 80}, 1, cv::LINE_AA);
  return canvas;
}

}  // namespace olt
