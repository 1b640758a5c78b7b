// The consistency score against a known scene: exact poses agree, a deliberately wrong one does not.
#include "olt/poses/consistency.h"

#include <catch2/catch.hpp>

#include "olt/poses/registration_poses.h"
#include "olt/registration/point_set.h"
#include "olt/source/synthetic.h"

using namespace olt;

TEST_CASE("consistency: exact poses put their points on the scene, a wrong pose is flagged") {
  SyntheticConfig sc;
  sc.frames = 8;
  sc.width = 320;
  sc.height = 240;
  const SyntheticScene scene = make_synthetic_scene(sc);
  SensorCalibration cal;
  cal.depth = cal.color = scene.camera;
  cal.depth_scale = sc.depth_scale;
  const RegistrationPosesConfig config;
  const RegistrationOdometry sampler({{"cam", cal}}, config, Pose::Identity());
  std::vector<std::vector<Eigen::Vector3d>> frames;
  std::vector<Eigen::Vector3d> world;
  for (size_t i = 0; i < scene.timestamps.size(); ++i) {
    const Observation o{std::to_string(i), "cam", scene.timestamps[i], {"", Digest()}, std::nullopt, 0};
    frames.push_back(sampler.sample_points(o, render_synthetic_frame(scene, i).depth));
    if (i % 2 == 0)  // the scene from every other frame, as keyframes make it
      for (const auto& p : frames.back()) world.push_back(scene.T_world_camera[i] * p);
  }
  const PointSet surface_set = downsampled_point_set(world, config.voxel_size_m, config.covariance_neighbors);
  const SceneSurface surface(surface_set.points, surface_set.normals);
  const ConsistencySetting setting;

  for (size_t i = 1; i < frames.size(); i += 2) {  // frames the scene was not made from
    const Consistency exact = surface.score(frames[i], scene.T_world_camera[i], setting);
    INFO("frame " << i << ": " << exact.fraction << " of " << exact.points << ", rmse " << exact.rmse_m);
    CHECK(exact.points > 500);
    CHECK(exact.coverage > 0.6);
    CHECK(exact.fraction > 0.95);
    CHECK(exact.rmse_m < 0.01);
  }
  // Frame 3 placed 8 cm along its optical axis and turned 3 degrees: its points float off the walls.
  Pose wrong = scene.T_world_camera[3];
  wrong.translation() += 0.08 * wrong.linear().col(2);
  wrong.linear() = wrong.linear() * Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Consistency off = surface.score(frames[3], wrong, setting);
  CHECK(off.fraction < setting.min_fraction);
  CHECK(off.rmse_m > 0.03);
}
