#pragma once
// A 6-DoF pose graph (Lu & Milios 1997; Grisetti et al., "A tutorial on graph-based SLAM", 2010):
// nodes are poses T_world_node, edges relative measurements Z_ij ~ T_i^-1 T_j with an information
// matrix. Gauss-Newton on the left-perturbed error e_ij = Log(T_i^-1 T_j Z_ij^-1), the form in
// which a registration of node j against node i (target in i's frame) reports its Hessian, so a
// registration's information enters unchanged. Robust: edges marked `robust` are re-weighted
// (Cauchy) by how far their error is from zero in degrees and metres, so one wrong loop closure
// cannot pull the graph apart.
#include <Eigen/Core>
#include <vector>

#include "olt/core/geometry.h"

namespace olt {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

struct PoseGraphEdge {
  size_t from = 0, to = 0;                      ///< node indices i, j
  Pose T_from_to = Pose::Identity();            ///< the measurement Z_ij
  Matrix6d information = Matrix6d::Identity();  ///< on (omega, v), rotation first, of e_ij
  bool robust = false;                          ///< Cauchy re-weighting (loop closures)
};

struct PoseGraphSetting {
  int max_iterations = 20;         ///< Gauss-Newton iterations at most
  double robust_scale_deg = 1.0;   ///< Cauchy scale of a robust edge's rotation error, degrees
  double robust_scale_m = 0.03;    ///< ... and of its translation error, metres
  double converged_update = 1e-7;  ///< stop when no node moves more than this (radians or metres)
};

struct PoseGraphResult {
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;  ///< sum of e^T W e (robust weights included)
  std::vector<double> edge_weights;         ///< final robust weight per edge (1 for plain edges)
};

/// The error of one edge at the nodes' poses: (omega, v) of T_i^-1 T_j Z_ij^-1.
Vector6d pose_graph_error(const Pose& T_i, const Pose& T_j, const Pose& Z_ij);

/// Adjoint of T on twists (omega, v): T exp(xi) T^-1 = exp(Ad_T xi).
Matrix6d adjoint(const Pose& T);

/// The twist (omega, v) as a pose: rotation exp(omega), translation v (first-order SE(3)).
Pose pose_from_twist(const Vector6d& twist);

/// Optimises `nodes` in place; node `fixed` does not move (the gauge).
PoseGraphResult optimize_pose_graph(std::vector<Pose>& nodes, const std::vector<PoseGraphEdge>& edges, size_t fixed,
                                    const PoseGraphSetting& setting = {});

}  // namespace olt
