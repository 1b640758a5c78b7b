// ATE and RPE against hand-computed values.
#include "olt/eval/trajectory_error.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace olt;

namespace {

Trajectory line(const std::vector<Eigen::Vector3d>& positions) {
  Trajectory t;
  for (size_t i = 0; i < positions.size(); ++i) t.push_back({static_cast<double>(i), Pose::Identity()});
  for (size_t i = 0; i < positions.size(); ++i) t[i].pose.translation() = positions[i];
  return t;
}

}  // namespace

TEST_CASE("a rigidly moved copy of the ground truth has zero ATE and RPE", "[eval]") {
  const Trajectory truth = line({{0, 0, 0}, {1, 0.2, 0}, {2, 0.1, 0.3}, {3, -0.4, 0.2}});
  Trajectory estimate = truth;
  const Pose move = pose_from_xyz_ypr_deg({5, -3, 1, 70, 10, -20});
  for (auto& s : estimate) s.pose = move * s.pose;
  const auto e = trajectory_errors(estimate, truth, 0.01);
  CHECK(e.matched == 4);
  CHECK(e.ate_m.rmse == Approx(0).margin(1e-9));
  CHECK(e.ate_deg.rmse == Approx(0).margin(1e-6));
  CHECK(e.rpe_frame_m.rmse == Approx(0).margin(1e-9));
  CHECK(e.rpe_frame_deg.rmse == Approx(0).margin(1e-6));
}

TEST_CASE("hand-computed ATE and RPE", "[eval]") {
  // Truth along x; the estimate is off by +-d in y in a pattern that leaves the alignment at the
  // identity (zero cross-covariance), and its last pose is turned 10 degrees about z.
  const double d = 0.1;
  const Trajectory truth = line({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  Trajectory estimate = line({{0, d, 0}, {1, -d, 0}, {2, -d, 0}, {3, d, 0}});
  estimate[3].pose.linear() = rotation_from_ypr_deg(10, 0, 0);
  const auto e = trajectory_errors(estimate, truth, 0.01);
  CHECK(e.T_groundtruth_estimate.translation().norm() == Approx(0).margin(1e-9));
  CHECK(e.ate_m.rmse == Approx(d));
  // consecutive relative translations (1, -2d), (1, 0), (1, 2d) against (1, 0): errors 2d, 0, 2d
  CHECK(e.rpe_frame_m.rmse == Approx(2 * d * std::sqrt(2.0 / 3.0)));
  CHECK(e.rpe_frame_m.max == Approx(2 * d));
  // only the last pair turns: 10 degrees once in three pairs
  CHECK(e.rpe_frame_deg.rmse == Approx(10 / std::sqrt(3.0)));
  // samples are 1 s apart, so the per-second figures are the per-frame ones
  CHECK(e.rpe_second_deg.rmse == Approx(e.rpe_frame_deg.rmse));
}

TEST_CASE("association by timestamp: nearest within the limit and each sample once", "[eval]") {
  Trajectory a = line({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}});
  Trajectory b = line({{0, 0, 0}, {0, 0, 0}});
  a[0].timestamp = 1.00, a[1].timestamp = 1.01, a[2].timestamp = 2.0;
  b[0].timestamp = 1.008, b[1].timestamp = 3.0;
  const auto pairs = associate_trajectories(a, b, 0.02);
  REQUIRE(pairs.size() == 1);
  CHECK(pairs[0] == std::make_pair<size_t, size_t>(1, 0));
}

TEST_CASE("interpolated ground truth removes the sampling offset that nearest association keeps", "[eval]") {
  // Truth at 0, 1, 2, 3 s moving 1 m/s along x; the estimate at 0.25, 1.25, 2.25 s lies exactly on it.
  const Trajectory truth = line({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  Trajectory estimate = line({{0.25, 0, 0}, {1.25, 0, 0}, {2.25, 0, 0}});
  for (auto& s : estimate) s.timestamp += 0.25;
  // Nearest association pairs with 0, 1, 2 s: a constant 0.25 m offset, absorbed by the alignment.
  const auto nearest = trajectory_errors(estimate, truth, 0.3, GroundTruthTiming::nearest);
  CHECK(nearest.matched == 3);
  CHECK(nearest.ate_m.rmse == Approx(0).margin(1e-9));
  // Rotating the truth between samples: nearest sees part of the turn as error, interpolation none.
  Trajectory turning = truth;
  for (size_t i = 0; i < turning.size(); ++i) turning[i].pose.linear() = rotation_from_ypr_deg(20.0 * i, 0, 0);
  for (size_t i = 0; i < estimate.size(); ++i)
    estimate[i].pose.linear() = rotation_from_ypr_deg(20.0 * (i + 0.25), 0, 0);
  estimate[2].pose.linear() = rotation_from_ypr_deg(20.0 * 2.25 + 3, 0, 0);  // the last turn 3 degrees too far
  const auto exact = trajectory_errors(estimate, turning, 0.3, GroundTruthTiming::interpolated);
  CHECK(exact.matched == 3);
  CHECK(exact.ate_m.rmse == Approx(0).margin(1e-9));
  CHECK(exact.rpe_frame_deg.max == Approx(3));
  CHECK(exact.rpe_frame_deg.rmse == Approx(3 / std::sqrt(2.0)));
  // Beyond max_dt from both samples around it, an estimate is left out.
  CHECK(trajectory_errors(estimate, turning, 0.2, GroundTruthTiming::interpolated).matched == 0);
}

TEST_CASE("ATE rotation after the rotation alignment, on a trajectory that barely translates", "[eval]") {
  // Like TUM fr1_rpy: the camera turns (+-15 degrees about every axis) in place; positions are
  // independent noise within 1 mm on both sides, so they determine no alignment rotation. The
  // estimate is in a frame turned by G against the ground truth's and each of its rotations is off
  // by 0.5 degrees about x, alternately one way and the other: rotation ATE 0.5 degrees.
  const Pose G = pose_from_xyz_ypr_deg({0.3, -0.2, 0.1, 40, -25, 10});
  std::mt19937 random(7);
  std::uniform_real_distribution<double> noise(-0.0005, 0.0005);
  auto jitter = [&] { return Eigen::Vector3d(noise(random), noise(random), noise(random)); };
  Trajectory truth, estimate;
  for (int k = 0; k < 60; ++k) {
    const double phase = 0.2 * k;
    Pose q = pose_from_xyz_ypr_deg({0, 0, 0, 15 * std::sin(phase), 15 * std::sin(0.7 * phase), 15 * std::cos(phase)});
    q.translation() = Eigen::Vector3d(1, 2, 1.5) + jitter();
    const Eigen::Matrix3d error =
        Eigen::AngleAxisd((k % 2 ? 0.5 : -0.5) * M_PI / 180, Eigen::Vector3d::UnitX()).matrix();
    Pose p = G * q;
    p.linear() = p.linear() * error;
    p.translation() = G * Eigen::Vector3d(1, 2, 1.5) + jitter();
    truth.push_back({0.1 * k, q});
    estimate.push_back({0.1 * k, p});
  }
  const auto e = trajectory_errors(estimate, truth, 0.01);
  CHECK(e.ate_deg.rmse == Approx(0.5).margin(0.005));
  CHECK(e.ate_deg.max == Approx(0.5).margin(0.01));
  CHECK(Eigen::AngleAxisd(e.R_groundtruth_estimate * G.linear()).angle() * 180 / M_PI < 0.01);
  CHECK(e.ate_m.rmse < 0.001);
  // What the rotation of the position alignment made of it (the figure before the fix): far off.
  double old_sq = 0;
  for (size_t k = 0; k < truth.size(); ++k)
    old_sq += std::pow(rotation_angle(truth[k].pose.inverse() * e.T_groundtruth_estimate * estimate[k].pose), 2);
  CHECK(std::sqrt(old_sq / truth.size()) * 180 / M_PI > 5);
}
