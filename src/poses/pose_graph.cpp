#include "olt/poses/pose_graph.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>

namespace olt {

Matrix6d adjoint(const Pose& T) {
  Matrix6d A = Matrix6d::Zero();
  const Eigen::Matrix3d R = T.linear();
  A.topLeftCorner<3, 3>() = R;
  A.bottomLeftCorner<3, 3>() = skew(T.translation()) * R;
  A.bottomRightCorner<3, 3>() = R;
  return A;
}

namespace {

double robust_weight(const Vector6d& e, const PoseGraphSetting& s) {
  const double r_rot = e.head<3>().norm() / (s.robust_scale_deg * M_PI / 180);
  const double r_trans = e.tail<3>().norm() / s.robust_scale_m;
  return 1.0 / (1.0 + r_rot * r_rot + r_trans * r_trans);  // Cauchy
}

}  // namespace

Vector6d pose_graph_error(const Pose& T_i, const Pose& T_j, const Pose& Z_ij) {
  const Pose E = T_i.inverse() * T_j * Z_ij.inverse();
  const Eigen::AngleAxisd aa(E.linear());
  Vector6d e;
  e.head<3>() = aa.angle() * aa.axis();
  e.tail<3>() = E.translation();
  return e;
}

Pose pose_from_twist(const Vector6d& xi) {
  Pose T = Pose::Identity();
  const Eigen::Vector3d omega = xi.head<3>();
  if (omega.norm() > 0) T.linear() = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
  T.translation() = xi.tail<3>();
  return T;
}

PoseGraphResult optimize_pose_graph(std::vector<Pose>& nodes, const std::vector<PoseGraphEdge>& edges, size_t fixed,
                                    const PoseGraphSetting& s) {
  PoseGraphResult result;
  result.edge_weights.assign(edges.size(), 1.0);
  const size_t n = nodes.size();
  if (n < 2 || edges.empty()) return result;
  const auto dim = static_cast<Eigen::Index>(6 * n);
  for (int iteration = 1; iteration <= s.max_iterations; ++iteration) {
    result.iterations = iteration;
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(edges.size() * 4 * 36 + n * 6);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(dim);
    double cost = 0;
    for (size_t k = 0; k < edges.size(); ++k) {
      const PoseGraphEdge& edge = edges[k];
      const Vector6d e = pose_graph_error(nodes[edge.from], nodes[edge.to], edge.T_from_to);
      const double w = edge.robust ? robust_weight(e, s) : 1.0;
      result.edge_weights[k] = w;
      const Matrix6d W = w * edge.information;
      cost += e.dot(W * e);
      // Nodes perturbed on the left, T <- exp(delta) T: d e / d delta_j = Ad(T_i^-1) = A and
      // d e / d delta_i = -A, to first order in e (the tutorial's Eq. 30 with the SE(3) adjoint).
      const Matrix6d A = adjoint(nodes[edge.from].inverse());
      const Matrix6d H = A.transpose() * W * A;
      const Vector6d b = A.transpose() * W * e;
      const size_t blocks[2] = {edge.from, edge.to};
      const double signs[2] = {-1, 1};
      for (int a = 0; a < 2; ++a) {
        g.segment<6>(static_cast<Eigen::Index>(6 * blocks[a])) += signs[a] * b;
        for (int c = 0; c < 2; ++c)
          for (int r = 0; r < 6; ++r)
            for (int col = 0; col < 6; ++col)
              triplets.emplace_back(static_cast<int>(6 * blocks[a]) + r, static_cast<int>(6 * blocks[c]) + col,
                                    signs[a] * signs[c] * H(r, col));
      }
    }
    if (iteration == 1) result.initial_cost = cost;
    result.final_cost = cost;
    // The fixed node is held by a stiff prior; a tiny damping keeps nodes no edge reaches in place.
    for (Eigen::Index r = 0; r < dim; ++r)
      triplets.emplace_back(static_cast<int>(r), static_cast<int>(r),
                            static_cast<size_t>(r) / 6 == fixed ? 1e12 : 1e-9);
    Eigen::SparseMatrix<double> H(dim, dim);
    H.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
    if (solver.info() != Eigen::Success) break;
    const Eigen::VectorXd delta = solver.solve(-g);
    if (!delta.allFinite()) break;
    double largest = 0;
    for (size_t i = 0; i < n; ++i) {
      const Vector6d d = delta.segment<6>(static_cast<Eigen::Index>(6 * i));
      largest = std::max(largest, d.cwiseAbs().maxCoeff());
      nodes[i] = pose_from_twist(d) * nodes[i];
      nodes[i].linear() = Eigen::Quaterniond(nodes[i].linear()).normalized().toRotationMatrix();
    }
    if (largest < s.converged_update) break;
  }
  return result;
}

}  // namespace olt
