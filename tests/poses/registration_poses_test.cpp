// Registration poses on the synthetic recording: accuracy against exact poses, and what the
// memory and key-pose options change.
#include "olt/poses/registration_poses.h"

#include <catch2/catch.hpp>

#include "olt/source/synthetic.h"

using namespace olt;

namespace {

struct Run {
  std::vector<ObservationPose> poses;
  SyntheticScene scene;
  KeyframeGraphSummary graph;
};

// `color_dt_s`: the colour images taken that long apart from depth (alternating sign); with
// `stamped`, the observations say so (else they claim both were taken together).
Run run(const RegistrationPosesConfig& config, int frames = 12, double color_dt_s = 0, bool stamped = true) {
  SyntheticConfig sc;
  sc.frames = frames;
  sc.width = 320;
  sc.height = 240;
  sc.color_dt_s = color_dt_s;
  Run out{{}, make_synthetic_scene(sc), {}};
  SensorCalibration cal;
  cal.depth = cal.color = out.scene.camera;
  cal.depth_scale = sc.depth_scale;
  RegistrationOdometry odometry({{"cam", cal}}, config, out.scene.T_world_camera[0]);
  for (int i = 0; i < frames; ++i) {
    const SyntheticFrame f = render_synthetic_frame(out.scene, static_cast<size_t>(i));
    char id[16];
    std::snprintf(id, sizeof(id), "%06d", i);
    const double dt = stamped ? out.scene.color_dt_s[static_cast<size_t>(i)] : 0.0;
    odometry.add({id, "cam", out.scene.timestamps[i], {"", Digest()}, {{"color.png", Digest()}}, dt}, f.depth,
                 [&] { return f.color; });
  }
  out.poses = odometry.finish();
  out.graph = odometry.graph_summary();
  return out;
}

// Depth alone: the geometric options' tests. The synthetic room is flat-coloured, so the colour
// term has only edges to work with there (its own tests are below and in photometric_test.cpp).
RegistrationPosesConfig depth_only() {
  RegistrationPosesConfig config;
  config.photometric_weight = 0;
  return config;
}

double worst_translation_error(const Run& r) {
  double worst = 0;
  for (size_t i = 0; i < r.poses.size(); ++i)
    worst = std::max(worst, (r.poses[i].T_world_sensor.translation() - r.scene.T_world_camera[i].translation()).norm());
  return worst;
}

}  // namespace

TEST_CASE("frame-to-frame GICP follows the exact synthetic trajectory") {
  const Run r = run(depth_only());
  REQUIRE(r.poses.size() == 12);
  for (const auto& p : r.poses) CHECK(p.valid);
  CHECK(worst_translation_error(r) < 0.01);
  const Pose last_error = r.poses.back().T_world_sensor.inverse() * r.scene.T_world_camera.back();
  CHECK(rotation_angle(last_error) * 180 / M_PI < 0.3);
}

TEST_CASE("with the colour term (the default) the flat-coloured synthetic room stays within 4 cm") {
  // The synthetic room has no texture: the colour term sees only edges, many of them where one
  // surface hides another and the colour mixes both. There it costs accuracy (depth alone: 1 mm
  // here); on real, textured recordings it gains (README, Registration). This bounds the cost.
  const RegistrationPosesConfig defaults;  // named: GCC 12 misreads a temporary's strings as uninitialised
  const Run r = run(defaults);
  REQUIRE(r.poses.size() == 12);
  for (size_t i = 1; i < r.poses.size(); ++i) {
    CHECK(r.poses[i].valid);
    CHECK(r.poses[i].quality.registration->fit->photometric_points.value_or(0) > 1000);
  }
  CHECK(worst_translation_error(r) < 0.04);  // measured: 2.9 cm
  const Pose last_error = r.poses.back().T_world_sensor.inverse() * r.scene.T_world_camera.back();
  CHECK(rotation_angle(last_error) * 180 / M_PI < 1.0);  // measured: 0.76 degrees
}

TEST_CASE("memory local_map registers against the last N observations") {
  RegistrationPosesConfig previous = depth_only(), local = depth_only();
  local.memory = RegistrationMemory::local_map;
  local.memory_size = 4;
  const Run a = run(previous, 8), b = run(local, 8);
  // The map grows with each of the first 4 observations, then holds 4: more than one observation's
  // points, and fewer than 4x as many, since the overlapping parts merge on the voxel grid.
  auto target_points = [](const Run& r, size_t i) {
    return static_cast<double>(r.poses[i].quality.registration->fit->target_points);
  };
  for (size_t i = 2; i < 5; ++i) CHECK(target_points(b, i) > target_points(b, i - 1));
  for (size_t i = 5; i < 8; ++i) {
    const double ratio = target_points(b, i) / target_points(a, i);
    CHECK(ratio > 1.5);
    CHECK(ratio < 4.0);
  }
  CHECK(worst_translation_error(b) < 0.01);
}

TEST_CASE("key poses: only observations that moved enough are registered - the others are interpolated") {
  RegistrationPosesConfig config = depth_only();
  // 24 frames: the synthetic camera moves about 0.17 m and 4.5 degrees of arc per frame
  config.key_distance_m = 0.4;
  config.key_angle_deg = 30;
  const Run r = run(config, 24);
  int keys = 0;
  const Pose* last_key = nullptr;
  for (const auto& p : r.poses) {
    if (!p.quality.registration->key) continue;
    ++keys;
    if (last_key && keys > 2) {  // the first two observations are always keys (they give the velocity)
      const Pose moved = last_key->inverse() * p.T_world_sensor;
      CHECK((moved.translation().norm() > 0.3 || rotation_angle(moved) * 180 / M_PI > 15));
    }
    last_key = &p.T_world_sensor;
  }
  CHECK(keys > 1);
  CHECK(keys < 12);
  // interpolated along the chord of the camera's arc: the sagitta of a 3-frame arc is about 1.5 cm
  CHECK(worst_translation_error(r) < 0.03);  // interpolated poses stay close to the truth
}

TEST_CASE("an initial guess from another pose source is used where registration cannot move far") {
  // With a single Gauss-Newton iteration the result stays near the guess: the exact trajectory
  // as guess keeps the poses exact, the previous pose as guess leaves them far behind.
  RegistrationPosesConfig from_truth = depth_only(), from_previous = depth_only();
  from_truth.solver.max_iterations = from_previous.solver.max_iterations = 1;
  from_truth.initial_guess = InitialGuess::trajectory;
  from_previous.initial_guess = InitialGuess::previous_pose;
  SyntheticConfig sc;
  sc.frames = 6;
  const SyntheticScene scene = make_synthetic_scene(sc);
  for (size_t i = 0; i < scene.timestamps.size(); ++i)
    from_truth.guess_trajectory.push_back({scene.timestamps[i], scene.T_world_camera[i]});
  CHECK(worst_translation_error(run(from_truth, 6)) < 0.005);
  CHECK(worst_translation_error(run(from_previous, 6)) > 0.1);
}

TEST_CASE("colour taken 20 ms apart from depth, stamped so, tracks as well as colour taken with it") {
  // The hand-held camera turns about 9 degrees per frame (90 degrees/s): 20 ms is 1.8 degrees
  // between the depth and the colour image. The colour camera is placed at its own time by the
  // velocity estimate; without that, the colour term pulls the poses towards the wrong view.
  const RegistrationPosesConfig config;
  const Run together = run(config, 12, 0.0);
  const Run apart = run(config, 12, 0.02);
  const Run apart_unmodelled = run(config, 12, 0.02, false);
  const double e_together = worst_translation_error(together), e_apart = worst_translation_error(apart),
               e_unmodelled = worst_translation_error(apart_unmodelled);
  INFO("worst error: together " << e_together << " m, apart " << e_apart << " m, apart unmodelled " << e_unmodelled
                                << " m");
  CHECK(e_apart < std::max(1.25 * e_together, e_together + 0.005));
  // Not asserted: on this flat-coloured room the colour term's own error (edges where surfaces
  // meet) is as large as the 1.8 degrees, so leaving the stamps out is not reliably worse here.
}

TEST_CASE("memory keyframes: frames chained to keyframes, keyframes linked by loop closures") {
  // 36 frames along the arc: the keyframes (every 0.1 m or 8 degrees) see what the ones before saw,
  // so each new one is registered against earlier ones besides its own chain.
  RegistrationPosesConfig config = depth_only();
  config.keyframe_distance_m = 0.2;
  const Run r = run(config, 36);
  int keyframes = 0;
  for (const auto& p : r.poses) {
    CHECK(p.valid);
    if (p.quality.registration->new_keyframe) ++keyframes;
  }
  CHECK(keyframes == r.graph.keyframes);
  CHECK(keyframes > 5);
  CHECK(keyframes < 30);
  CHECK(r.graph.loop_closures > 0);
  CHECK(worst_translation_error(r) < 0.01);
}
