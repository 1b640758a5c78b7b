#pragma once
// A 2D world of wall segments and an exact laser scanner in it, for scan-matching tests.
#include <random>
#include <vector>

#include "olt/model/laser.h"

namespace olt::test {

struct Segment {
  Eigen::Vector2d a, b;
};

/// An L-shaped room (8 x 6 m with a 3 x 2 m corner cut off) with two pillars: no symmetry that
/// could let a match slide.
inline std::vector<Segment> l_shaped_room() {
  const std::vector<Eigen::Vector2d> outline = {{-3, -2}, {5, -2}, {5, 2}, {2, 2}, {2, 4}, {-3, 4}};
  std::vector<Segment> walls;
  for (size_t i = 0; i < outline.size(); ++i) walls.push_back({outline[i], outline[(i + 1) % outline.size()]});
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(1.5, 0.8), Eigen::Vector2d(-1.2, 2.0)}) {  // 0.4 m square pillars
    const Eigen::Vector2d d(0.2, 0.2), e(0.2, -0.2);
    walls.push_back({c - d, c + e});
    walls.push_back({c + e, c + d});
    walls.push_back({c + d, c - e});
    walls.push_back({c - e, c - d});
  }
  return walls;
}

/// The points (robot frame) a 360-ray, 270-degree scanner at the robot's origin sees from `pose`,
/// with Gaussian range noise of `sigma_m`.
inline std::vector<Eigen::Vector2d> cast_scan(const std::vector<Segment>& world, const Pose2& pose, double sigma_m,
                                              unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, sigma_m > 0 ? sigma_m : 1);
  std::vector<Eigen::Vector2d> points;
  for (int k = 0; k < 360; ++k) {
    const double angle = (-135 + 270.0 * k / 359) * M_PI / 180;
    const Eigen::Vector2d o = pose.translation();
    const Eigen::Vector2d d = pose.linear() * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    double best = 1e9;
    for (const auto& s : world) {
      const Eigen::Vector2d e = s.b - s.a;
      const double det = d.x() * (-e.y()) - d.y() * (-e.x());
      if (std::abs(det) < 1e-12) continue;
      const Eigen::Vector2d r = s.a - o;
      const double t = (r.x() * (-e.y()) - r.y() * (-e.x())) / det;
      const double u = (d.x() * r.y() - d.y() * r.x()) / det;
      if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
    }
    if (best > 30) continue;
    const double range = best + (sigma_m > 0 ? noise(rng) : 0);
    points.emplace_back(range * std::cos(angle), range * std::sin(angle));
  }
  return points;
}

}  // namespace olt::test
