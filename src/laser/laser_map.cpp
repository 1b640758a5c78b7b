#include "olt/laser/laser_map.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <deque>
#include <functional>
#include <optional>

#include "olt/core/parallel.h"
#include "olt/core/progress.h"

namespace olt {
namespace {

struct Keyframe {
  size_t scan = 0;                               // index of its scan
  std::vector<Eigen::Vector2d> points, normals;  // robot frame
};

// One scan matched against `map` from `guess`; invalid (keeping the guess) when the match fails.
ScanPose locate(const PointMap2D& map, const std::vector<Eigen::Vector2d>& points, const LaserScan& scan,
                const Pose2& guess, const LaserMapSettings& s) {
  ScanPose p;
  p.timestamp = scan.timestamp;
  p.T_map_robot = guess;
  if (map.size() == 0) {
    p.valid = false;
    p.flag = "the map is empty";
    return p;
  }
  p.match = match_scan(map, points, guess, s.matching);
  if (p.match.inlier_ratio < s.min_inlier_ratio || p.match.rmse_m > s.max_rmse_m) {
    p.valid = false;
    char why[160];
    std::snprintf(why, sizeof(why), "scan match failed: %.0f%% inliers, RMSE %.3f m", 100 * p.match.inlier_ratio,
                  p.match.rmse_m);
    p.flag = why;
  } else {
    p.T_map_robot = p.match.T_map_robot;
  }
  return p;
}

Pose2 odometry_increment(const std::vector<OdometrySample>& odometry, double from, double to) {
  return odometry_at(odometry, from).inverse() * odometry_at(odometry, to);
}

// The keyframes [first, last) at poses `at` (by keyframe) as one map.
PointMap2D map_of(const Keyframe* keys, const Pose2* at, size_t first, size_t last, double cell_m) {
  PointMap2D map(cell_m);
  for (size_t k = first; k < last; ++k) {
    std::vector<Eigen::Vector2d> points = keys[k].points, normals = keys[k].normals;
    for (auto& q : points) q = at[k] * q;
    for (auto& n : normals) n = at[k].linear() * n;
    map.add(points, normals);
  }
  map.build();
  return map;
}

struct Edge {
  size_t a, b;
  Pose2 z;  // measured T_a^-1 T_b
};

// Gauss-Newton over the keyframe poses (the first one fixed): each edge wants T_a^-1 T_b = z, with
// 2 cm and 0.2 degrees of standard deviation. The normal equations are sparse (a block per edge):
// a sparse Cholesky keeps long runs, thousands of keyframes, cheap.
void optimize_pose_graph(std::vector<Pose2>& poses, const std::vector<Edge>& edges) {
  const Eigen::Index n = static_cast<Eigen::Index>(poses.size());
  const Eigen::Vector3d information(1 / (0.02 * 0.02), 1 / (0.02 * 0.02), 1 / std::pow(0.2 * M_PI / 180, 2));
  const Eigen::Matrix3d W = information.asDiagonal();
  for (int iteration = 0; iteration < 10; ++iteration) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(edges.size() * 36 + 3);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * n);
    auto add_block = [&](Eigen::Index row, Eigen::Index col, const Eigen::Matrix3d& block) {
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) triplets.emplace_back(row + r, col + c, block(r, c));
    };
    for (const Edge& e : edges) {
      const Eigen::Matrix2d Ra = poses[e.a].linear(), Rz = e.z.linear();
      const Eigen::Vector2d dt = poses[e.b].translation() - poses[e.a].translation();
      Eigen::Vector3d r;
      r.head<2>() = Rz.transpose() * (Ra.transpose() * dt - e.z.translation());
      r(2) = std::remainder(heading(poses[e.b]) - heading(poses[e.a]) - heading(e.z), 2 * M_PI);
      Eigen::Matrix2d dRaT;  // d(Ra^T)/d(theta_a)
      dRaT << -Ra(1, 0), Ra(0, 0), -Ra(0, 0), -Ra(1, 0);
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), B = Eigen::Matrix3d::Zero();
      A.topLeftCorner<2, 2>() = -Rz.transpose() * Ra.transpose();
      A.topRightCorner<2, 1>() = Rz.transpose() * dRaT * dt;
      A(2, 2) = -1;
      B.topLeftCorner<2, 2>() = Rz.transpose() * Ra.transpose();
      B(2, 2) = 1;
      const Eigen::Index a = 3 * static_cast<Eigen::Index>(e.a), b = 3 * static_cast<Eigen::Index>(e.b);
      add_block(a, a, A.transpose() * W * A);
      add_block(a, b, A.transpose() * W * B);
      add_block(b, a, B.transpose() * W * A);
      add_block(b, b, B.transpose() * W * B);
      g.segment<3>(a) += A.transpose() * W * r;
      g.segment<3>(b) += B.transpose() * W * r;
    }
    add_block(0, 0, 1e12 * Eigen::Matrix3d::Identity());  // the first keyframe stays put
    Eigen::SparseMatrix<double> H(3 * n, 3 * n);
    H.setFromTriplets(triplets.begin(), triplets.end());  // duplicates are summed
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
    if (solver.info() != Eigen::Success) return;
    const Eigen::VectorXd step = solver.solve(-g);
    if (!step.allFinite()) return;
    for (Eigen::Index k = 0; k < n; ++k) {
      const Eigen::Vector3d d = step.segment<3>(3 * k);
      poses[k] = pose2(poses[k].translation().x() + d(0), poses[k].translation().y() + d(1), heading(poses[k]) + d(2));
    }
    if (step.lpNorm<Eigen::Infinity>() < 1e-7) return;
  }
}

// The work that matches keyframe k against the keyframes around a place seen long before (the
// nearest keyframe at least `loop_min_keyframes` earlier, within loop_radius_m, by the tracking's
// poses); none where no place is near (found here: a pass over the poses, cheaper than waking a
// thread). Its edge goes to `out`, left empty where the match fails. It reads keyframes and poses
// 0 ... k, which the tracking neither changes nor moves (both lists have room for every scan).
std::function<void()> loop_match(const Keyframe* keys, const Pose2* poses, size_t k, const LaserMapSettings& s,
                                 std::optional<Edge>& out) {
  const size_t gap = static_cast<size_t>(std::max(1, s.loop_min_keyframes));
  if (s.loop_radius_m <= 0 || k < gap) return {};
  size_t best = k;
  double best_distance = s.loop_radius_m;
  for (size_t j = 0; j + gap <= k; ++j) {
    const double d = (poses[j].translation() - poses[k].translation()).norm();
    if (d < best_distance) {
      best_distance = d;
      best = j;
    }
  }
  if (best == k) return {};
  return [keys, poses, k, best, gap, &s, &out] {
    const size_t first = best >= 2 ? best - 2 : 0, last = std::min(best + 3, k + 1 - gap);
    const ScanMatch m =
        match_scan(map_of(keys, poses, first, last, s.map_cell_m), keys[k].points, poses[k], s.matching);
    if (m.inlier_ratio < s.loop_min_inlier_ratio || m.rmse_m > s.loop_max_rmse_m) return;
    out = Edge{best, k, poses[best].inverse() * m.T_map_robot};
  };
}

}  // namespace

LaserMap build_laser_map(const std::vector<LaserScan>& scans, const std::vector<OdometrySample>& odometry,
                         const LaserMapSettings& s) {
  LaserMap result{PointMap2D(s.map_cell_m), {}, 0};
  // At most a keyframe a scan: with room for every scan, neither list moves while the loop matches
  // read it.
  std::vector<Keyframe> keys;
  std::vector<Pose2> key_poses;
  keys.reserve(scans.size());
  key_poses.reserve(scans.size());
  std::vector<size_t> key_of_scan;  // the last keyframe at or before each scan
  PointMap2D local(s.map_cell_m);
  // Each keyframe's loop match, worked on by the other threads while the tracking goes on (the
  // tracking itself is one scan after another); a deque, so that a match's slot stays put.
  std::deque<std::optional<Edge>> loops;
  Background loop_matches;
  // Tracking against the recent keyframes.
  Progress tracked("laser map: scans tracked", scans.size());
  for (size_t i = 0; i < scans.size(); ++i) {
    const Pose2 guess = i == 0 ? Pose2::Identity()
                               : result.poses.back().T_map_robot *
                                     odometry_increment(odometry, scans[i - 1].timestamp, scans[i].timestamp);
    const std::vector<Eigen::Vector2d> points = scan_points(scans[i], s.min_range_m, s.max_range_m);
    ScanPose p = locate(local, points, scans[i], guess, s);
    if (keys.empty()) p = ScanPose{scans[i].timestamp, guess, {}, false, true, ""};
    bool key = keys.empty();
    if (!key && p.valid) {
      const Pose2 moved = key_poses.back().inverse() * p.T_map_robot;
      key = moved.translation().norm() >= s.key_distance_m || std::abs(heading(moved)) >= s.key_angle_deg * M_PI / 180;
    }
    if (key && !points.empty()) {
      keys.push_back({i, points, scan_normals(points)});
      key_poses.push_back(p.T_map_robot);
      p.key = true;
      if (auto match = loop_match(keys.data(), key_poses.data(), keys.size() - 1, s, loops.emplace_back()))
        loop_matches.run(std::move(match));
      const size_t window = static_cast<size_t>(std::max(1, s.local_keyframes));
      local = map_of(keys.data(), key_poses.data(), keys.size() > window ? keys.size() - window : 0, keys.size(),
                     s.map_cell_m);
    }
    key_of_scan.push_back(keys.empty() ? 0 : keys.size() - 1);
    result.poses.push_back(p);
    tracked.advance();
  }
  loop_matches.wait();
  if (keys.empty()) return result;

  // Loop closure: keyframes back at a place seen long before, matched against it, join the
  // consecutive keyframes' edges in the pose graph.
  std::vector<Edge> edges;
  for (size_t k = 1; k < keys.size(); ++k) edges.push_back({k - 1, k, key_poses[k - 1].inverse() * key_poses[k]});
  for (const auto& loop : loops)
    if (loop) {
      edges.push_back(*loop);
      ++result.loop_closures;
    }
  std::vector<Pose2> optimized = key_poses;
  if (result.loop_closures > 0) optimize_pose_graph(optimized, edges);

  // Every scan follows its keyframe; the map is every keyframe at its optimised pose.
  for (size_t i = 0; i < scans.size(); ++i) {
    const size_t k = key_of_scan[i];
    result.poses[i].T_map_robot = optimized[k] * key_poses[k].inverse() * result.poses[i].T_map_robot;
  }
  result.map = map_of(keys.data(), optimized.data(), 0, keys.size(), s.map_cell_m);
  return result;
}

std::vector<ScanPose> localize_scans(const PointMap2D& map, const std::vector<LaserScan>& scans,
                                     const std::vector<OdometrySample>& odometry, const LaserMapSettings& s,
                                     const Pose2& T_map_robot_first) {
  std::vector<ScanPose> poses;
  Progress localized("laser poses: scans localized", scans.size());
  for (size_t i = 0; i < scans.size(); ++i) {
    localized.advance();
    const Pose2 guess =
        i == 0 ? T_map_robot_first
               : poses.back().T_map_robot * odometry_increment(odometry, scans[i - 1].timestamp, scans[i].timestamp);
    poses.push_back(locate(map, scan_points(scans[i], s.min_range_m, s.max_range_m), scans[i], guess, s));
  }
  return poses;
}

}  // namespace olt
