// The pose graph against known answers: a loop whose odometry drifts is closed by one exact loop
// edge; a wrong loop closure is down-weighted by the robust kernel.
#include "olt/poses/pose_graph.h"

#include <catch2/catch.hpp>
#include <cmath>

using namespace olt;

namespace {

// A camera on a circle of radius 2 m, looking outwards, n poses around it.
std::vector<Pose> circle(int n) {
  std::vector<Pose> poses;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    Pose T = Pose::Identity();
    T.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(2 * std::cos(a), 2 * std::sin(a), 0.1 * std::sin(3 * a));
    poses.push_back(T);
  }
  return poses;
}

Matrix6d information(double rotation_sigma_rad, double translation_sigma_m) {
  Vector6d d;
  d << Eigen::Vector3d::Constant(1 / (rotation_sigma_rad * rotation_sigma_rad)),
      Eigen::Vector3d::Constant(1 / (translation_sigma_m * translation_sigma_m));
  return d.asDiagonal();
}

// Odometry that turns 1 % too much about z and drifts 1 cm up per step, chained from the first pose.
struct Drifted {
  std::vector<Pose> chained;
  std::vector<PoseGraphEdge> edges;
};

Drifted drifted_odometry(const std::vector<Pose>& truth) {
  Drifted d;
  d.chained.push_back(truth[0]);
  for (size_t i = 1; i < truth.size(); ++i) {
    Pose Z = truth[i - 1].inverse() * truth[i];
    const Eigen::AngleAxisd aa(Z.linear());
    Z.linear() = Eigen::AngleAxisd(aa.angle() * 1.01, aa.axis()).toRotationMatrix();
    Z.translation() += Eigen::Vector3d(0, 0, 0.01);
    d.edges.push_back({i - 1, i, Z, information(0.01, 0.01), false});
    d.chained.push_back(d.chained.back() * Z);
  }
  return d;
}

double worst_error_m(const std::vector<Pose>& a, const std::vector<Pose>& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, (a[i].translation() - b[i].translation()).norm());
  return worst;
}

}  // namespace

TEST_CASE("pose graph: the error of an edge is zero at its measurement and its twist otherwise") {
  const std::vector<Pose> truth = circle(8);
  const Pose Z = truth[2].inverse() * truth[3];
  CHECK(pose_graph_error(truth[2], truth[3], Z).norm() < 1e-12);
  Vector6d twist;
  twist << 0.01, -0.02, 0.005, 0.03, 0.0, -0.01;
  // T_j moved by exp(twist) in T_i's frame: the error is that twist (to first order).
  const Pose moved = truth[2] * pose_from_twist(twist) * truth[2].inverse() * truth[3];
  CHECK((pose_graph_error(truth[2], moved, Z) - twist).norm() < 1e-3);
}

TEST_CASE("pose graph: one exact loop closure undoes the drift of a 24-pose loop") {
  const std::vector<Pose> truth = circle(24);
  Drifted d = drifted_odometry(truth);
  const double drift = worst_error_m(d.chained, truth);
  REQUIRE(drift > 0.2);  // the chained odometry is far off by the end of the loop
  // The last pose sees the first again: an exact relative measurement, far more certain.
  d.edges.push_back({0, truth.size() - 1, truth[0].inverse() * truth.back(), information(0.001, 0.001), true});
  std::vector<Pose> nodes = d.chained;
  const PoseGraphResult r = optimize_pose_graph(nodes, d.edges, 0);
  CHECK(r.final_cost < r.initial_cost);
  CHECK((nodes[0].matrix() - truth[0].matrix()).norm() < 1e-9);  // the fixed node did not move
  // What is left is the odometry's own bias spread over the loop: a few centimetres at most.
  CHECK(worst_error_m(nodes, truth) < 0.2 * drift);
  CHECK((nodes.back().translation() - truth.back().translation()).norm() < 0.01);
}

TEST_CASE("pose graph: a wrong loop closure is down-weighted, not followed") {
  // Exact odometry and two loop closures on pose 12: a right one and one that claims it sits 15 cm
  // and 5 degrees away (within what close_loops' gate lets through), each as certain as the odometry.
  const std::vector<Pose> truth = circle(24);
  std::vector<PoseGraphEdge> edges;
  for (size_t i = 1; i < truth.size(); ++i)
    edges.push_back({i - 1, i, truth[i - 1].inverse() * truth[i], information(0.01, 0.01), false});
  edges.push_back({0, 12, truth[0].inverse() * truth[12], information(0.01, 0.01), true});
  Pose wrong = truth[0].inverse() * truth[12];
  wrong.translation() += Eigen::Vector3d(0.15, 0, 0);
  wrong.linear() = wrong.linear() * Eigen::AngleAxisd(5 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  edges.push_back({0, 12, wrong, information(0.01, 0.01), true});
  std::vector<Pose> nodes = truth;
  const PoseGraphResult r = optimize_pose_graph(nodes, edges, 0);
  CHECK(r.edge_weights.back() < 0.05);
  CHECK(r.edge_weights[r.edge_weights.size() - 2] > 0.9);
  CHECK(worst_error_m(nodes, truth) < 0.01);  // a plain least-squares mean would move pose 12 by ~5 cm
}
