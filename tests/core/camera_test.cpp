#include "olt/core/camera.h"

#include <catch2/catch.hpp>

using namespace olt;

TEST_CASE("pixel rays undistort exactly what project distorts") {
  Intrinsics c{640, 480, 517.3, 516.5, 318.6, 255.3, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}};
  const auto rays = pixel_rays(c);
  REQUIRE(rays.size() == 640u * 480u);
  double worst = 0;
  for (int v = 40; v < 440; v += 37) {
    for (int u = 40; u < 600; u += 41) {
      const auto& r = rays[static_cast<size_t>(v) * 640 + u];
      Eigen::Vector2d px;
      REQUIRE(project(c, Eigen::Vector3d(r.x() * 2.0, r.y() * 2.0, 2.0), &px));
      worst = std::max(worst, (px - Eigen::Vector2d(u, v)).norm());
    }
  }
  CHECK(worst < 0.01);
}

TEST_CASE("without distortion a ray is ((u - cx) / fx - (v - cy) / fy)") {
  Intrinsics c{4, 3, 2.0, 4.0, 1.0, 1.0, {}};
  const auto rays = pixel_rays(c);
  CHECK(rays[2 * 4 + 3].isApprox(Eigen::Vector2f(1.0f, 0.25f)));
  Eigen::Vector2d px;
  CHECK_FALSE(project(c, Eigen::Vector3d(0, 0, -1), &px));
}

TEST_CASE("the projection's Jacobian matches central differences of the distorted projection") {
  Intrinsics c{640, 480, 517.3, 516.5, 318.6, 255.3, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}};
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.1, -0.05, 1.5), Eigen::Vector3d(-0.9, 0.6, 1.8), Eigen::Vector3d(1.0, 0.8, 2.0)}) {
    Eigen::Vector2d px;
    Eigen::Matrix<double, 2, 3> J;
    REQUIRE(project(c, p, &px, &J));
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-6;
      Eigen::Vector2d plus, minus;
      project(c, p + h * Eigen::Vector3d::Unit(k), &plus);
      project(c, p - h * Eigen::Vector3d::Unit(k), &minus);
      const Eigen::Vector2d numeric = (plus - minus) / (2 * h);
      INFO("point " << p.transpose() << ", axis " << k);
      CHECK((J.col(k) - numeric).norm() < 1e-4 * std::max(1.0, numeric.norm()));
    }
  }
}
