// Registration recovers a known rigid transform between a synthetic cloud and its moved copy.
#include "olt/registration/registration.h"

#include <catch2/catch.hpp>

#include "olt/source/synthetic.h"

using namespace olt;

namespace {

// The synthetic room seen from the first camera pose, back-projected, 2 cm voxels.
PointSet room_cloud() {
  SyntheticConfig config;
  config.frames = 1;
  config.width = 320;
  config.height = 240;
  const SyntheticScene scene = make_synthetic_scene(config);
  const SyntheticFrame frame = render_synthetic_frame(scene, 0);
  std::vector<Eigen::Vector3d> points;
  const Intrinsics& c = scene.camera;
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) {
      const double z = frame.depth.at<uint16_t>(v, u) / config.depth_scale;
      if (z > 0) points.emplace_back((u - c.cx) / c.fx * z, (v - c.cy) / c.fy * z, z);
    }
  return downsampled_point_set(points, 0.02, 10);
}

}  // namespace

TEST_CASE("GICP and point-to-plane ICP recover a known transform to 1 mm and 0.1 degree") {
  const PointSet target = room_cloud();
  REQUIRE(target.size() > 2000);
  const KdTree tree(target.points);
  const Pose T_target_source = pose_from_xyz_ypr_deg({0.04, -0.03, 0.05, 4, -2, 3});
  // The source is the same cloud seen from the moved frame: p_source = T_target_source^-1 p_target.
  const PointSet source = transformed(target, T_target_source.inverse());
  for (const RegistrationMethod method : {RegistrationMethod::gicp, RegistrationMethod::icp}) {
    INFO("method " << (method == RegistrationMethod::gicp ? "gicp" : "icp"));
    RegistrationSetting setting;
    setting.method = method;
    setting.max_iterations = 50;
    const RegistrationResult r = register_point_sets(target, tree, source, Pose::Identity(), setting);
    const Pose error = r.T_target_source.inverse() * T_target_source;
    CHECK(r.converged);
    CHECK(error.translation().norm() < 0.001);
    CHECK(rotation_angle(error) * 180 / M_PI < 0.1);
    CHECK(r.inlier_ratio > 0.95);
    CHECK(r.rmse_m < 0.005);
  }
}

TEST_CASE("voxel downsampling keeps one centroid per voxel") {
  const auto out = voxel_downsample({{0.01, 0.01, 0.01}, {0.03, 0.01, 0.01}, {0.25, 0, 0}}, 0.1);
  REQUIRE(out.size() == 2);
  CHECK(out[0].isApprox(Eigen::Vector3d(0.02, 0.01, 0.01)));
}

TEST_CASE("covariances of points on a plane are flat along its normal") {
  PointSet set;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) set.points.emplace_back(0.01 * i, 0.01 * j, 1.0);
  const KdTree tree(set.points);
  estimate_covariances(set, tree, 10);
  const Eigen::Vector3d n = set.normals[55];
  CHECK(std::abs(n.z()) == Approx(1).margin(1e-9));
  CHECK((n.transpose() * set.covariances[55] * n)(0) == Approx(1e-3).margin(1e-9));
}
