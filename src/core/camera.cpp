#include "olt/core/camera.h"

#include <algorithm>

#include "olt/core/parallel.h"
#include "olt/core/undistort.h"

namespace olt {

bool Intrinsics::distorted() const {
  for (double d : distortion)
    if (d != 0.0) return true;
  return false;
}

std::vector<Eigen::Vector2f> pixel_rays(const Intrinsics& camera) {
  const size_t n = static_cast<size_t>(camera.width) * camera.height;
  std::vector<Eigen::Vector2f> rays(n);
  if (!camera.distorted()) {
    for (int v = 0; v < camera.height; ++v)
      for (int u = 0; u < camera.width; ++u)
        rays[static_cast<size_t>(v) * camera.width + u] = Eigen::Vector2f(
            static_cast<float>((u - camera.cx) / camera.fx), static_cast<float>((v - camera.cy) / camera.fy));
    return rays;
  }
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  const std::vector<double> d(camera.distortion.begin(), camera.distortion.end());
  const auto& undistort = undistorter();  // loaded once, before the threads
  // Each pixel undistorted on its own (iteratively): blocks of rows in parallel give the same rays.
  constexpr int kRows = 32;
  parallel_for(static_cast<size_t>((camera.height + kRows - 1) / kRows), [&](size_t block) {
    const int first = static_cast<int>(block) * kRows, last = std::min(camera.height, first + kRows);
    std::vector<cv::Point2f> pixels, normalised;
    for (int v = first; v < last; ++v)
      for (int u = 0; u < camera.width; ++u) pixels.emplace_back(u, v);
    undistort.points(pixels, K, d, normalised);
    const size_t start = static_cast<size_t>(first) * camera.width;
    for (size_t i = 0; i < normalised.size(); ++i) rays[start + i] = Eigen::Vector2f(normalised[i].x, normalised[i].y);
  });
  return rays;
}

bool project(const Intrinsics& c, const Eigen::Vector3d& p, Eigen::Vector2d* pixel,
             Eigen::Matrix<double, 2, 3>* jacobian) {
  if (p.z() <= 0) return false;
  const double x = p.x() / p.z(), y = p.y() / p.z();
  const auto& d = c.distortion;  // k1 k2 p1 p2 k3
  const double r2 = x * x + y * y;
  const double radial = 1 + d[0] * r2 + d[1] * r2 * r2 + d[4] * r2 * r2 * r2;
  const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
  const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
  *pixel = Eigen::Vector2d(c.fx * xd + c.cx, c.fy * yd + c.cy);
  if (jacobian) {
    // d pixel / d (x, y), the distortion model differentiated, times d (x, y) / d p.
    const double dradial_dr2 = d[0] + 2 * d[1] * r2 + 3 * d[4] * r2 * r2;
    const double dradial_dx = 2 * x * dradial_dr2, dradial_dy = 2 * y * dradial_dr2;
    Eigen::Matrix2d D;
    D << radial + x * dradial_dx + 2 * d[2] * y + 6 * d[3] * x, x * dradial_dy + 2 * d[2] * x + 2 * d[3] * y,
        y * dradial_dx + 2 * d[2] * x + 2 * d[3] * y, radial + y * dradial_dy + 6 * d[2] * y + 2 * d[3] * x;
    Eigen::Matrix<double, 2, 3> N;
    N << 1 / p.z(), 0, -x / p.z(), 0, 1 / p.z(), -y / p.z();
    *jacobian = Eigen::Vector2d(c.fx, c.fy).asDiagonal() * D * N;
  }
  return true;
}

}  // namespace olt
