#include "olt/core/geometry.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace olt {

Eigen::Matrix3d rotation_from_ypr_deg(double yaw_deg, double pitch_deg, double roll_deg) {
  const double k = M_PI / 180.0;
  return (Eigen::AngleAxisd(yaw_deg * k, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch_deg * k, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_deg * k, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Matrix3d rotation_zyx(const Eigen::Vector3d& a) {
  return (Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Matrix3d rotation_xyz(const Eigen::Vector3d& a) {
  return (Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

// Explicit decompositions keep the first and last angles in (-pi, pi] and the middle one in
// [-pi/2, pi/2] (Eigen's eulerAngles puts the first in [0, pi], which turns a -30 degree yaw into
// an equivalent but surprising triple).
Eigen::Vector3d angles_zyx(const Eigen::Matrix3d& R) {  // R = Rz(c) Ry(b) Rx(a)
  const double b = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  return {std::atan2(R(2, 1), R(2, 2)), b, std::atan2(R(1, 0), R(0, 0))};
}

Eigen::Vector3d angles_xyz(const Eigen::Matrix3d& R) {  // R = Rx(a) Ry(b) Rz(c)
  const double b = std::asin(std::clamp(R(0, 2), -1.0, 1.0));
  return {std::atan2(-R(1, 2), R(2, 2)), b, std::atan2(-R(0, 1), R(0, 0))};
}

Pose pose_from_xyz_ypr_deg(const std::array<double, 6>& v) {
  Pose pose = Pose::Identity();
  pose.linear() = rotation_from_ypr_deg(v[3], v[4], v[5]);
  pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return pose;
}

Pose pose_from_tq(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  Pose pose = Pose::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = t;
  return pose;
}

Pose interpolate(const Pose& a, const Pose& b, double f) {
  const Eigen::Quaterniond qa(a.linear());
  const Eigen::Quaterniond qb(b.linear());
  return pose_from_tq((1.0 - f) * a.translation() + f * b.translation(), qa.slerp(f, qb));
}

namespace {

Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// The left Jacobian of SO(3) at rotation vector w: t = V(w) u relates the translation of exp((w, u))
// to its tangent u.
Eigen::Matrix3d left_jacobian(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d W = hat(w);
  if (theta < 1e-9) return Eigen::Matrix3d::Identity() + 0.5 * W;
  return Eigen::Matrix3d::Identity() + (1 - std::cos(theta)) / (theta * theta) * W +
         (theta - std::sin(theta)) / (theta * theta * theta) * W * W;
}

}  // namespace

Pose interpolate_geodesic(const Pose& a, const Pose& b, double f) {
  const Pose d = a.inverse() * b;
  const Eigen::AngleAxisd aa(d.linear());
  const Eigen::Vector3d w = aa.angle() * aa.axis();
  const Eigen::Vector3d u = left_jacobian(w).inverse() * d.translation();
  Pose step = Pose::Identity();
  step.linear() = Eigen::AngleAxisd(f * aa.angle(), aa.axis()).toRotationMatrix();
  step.translation() = left_jacobian(f * w) * (f * u);
  return a * step;
}

Pose mrpt_camera_from_optical() {
  Pose T = Pose::Identity();
  T.linear().col(0) = Eigen::Vector3d(0, -1, 0);  // optical x (right) is MRPT -y
  T.linear().col(1) = Eigen::Vector3d(0, 0, -1);  // optical y (down) is MRPT -z
  T.linear().col(2) = Eigen::Vector3d(1, 0, 0);   // optical z (forward) is MRPT x
  return T;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

double rotation_angle(const Pose& pose) { return Eigen::AngleAxisd(pose.linear()).angle(); }

// The rotation R minimising sum_k ||R R_est_k - R_gt_k||_F^2, i.e. maximising trace(R^T H) with
// H = sum_k R_gt_k R_est_k^T: H's projection onto SO(3), H = U S V^T -> R = U diag(1, 1, det(U V^T)) V^T
// (orthogonal Procrustes with Umeyama's sign correction, so that R is a rotation, not a reflection).
Eigen::Matrix3d rotation_alignment(const std::vector<Pose>& P, const std::vector<Pose>& Q) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < P.size(); ++k) H += Q[k].linear() * P[k].linear().transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sign(1, 1, (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1);
  return svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
}

Pose pose_alignment(const std::vector<Pose>& P, const std::vector<Pose>& Q) {
  Pose T = Pose::Identity();
  if (P.empty()) return T;
  T.linear() = rotation_alignment(P, Q);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < P.size(); ++k) sum += Q[k].translation() - T.linear() * P[k].translation();
  T.translation() = sum / static_cast<double>(P.size());
  return T;
}

nlohmann::json pose_to_json(const Pose& pose) {
  Eigen::Quaterniond q(pose.linear());
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d& t = pose.translation();
  return {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
}

Pose pose_from_json(const nlohmann::json& v) {
  return pose_from_tq(Eigen::Vector3d(v.at(0), v.at(1), v.at(2)),
                      Eigen::Quaterniond(v.at(6).get<double>(), v.at(3), v.at(4), v.at(5)));
}

}  // namespace olt
