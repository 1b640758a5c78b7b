#pragma once
// Rigid transforms. Names follow frames: T_world_sensor maps a point from the sensor frame into the
// world frame (p_world = T_world_sensor * p_sensor).
#include <Eigen/Geometry>
#include <array>
#include <nlohmann/json.hpp>
#include <vector>

namespace olt {

using Pose = Eigen::Isometry3d;

/// Intrinsic Z-Y'-X'' rotation (yaw about z, then pitch about the new y, then roll about the new x),
/// the original toolkit's convention: R = Rz(yaw) * Ry(pitch) * Rx(roll).
Eigen::Matrix3d rotation_from_ypr_deg(double yaw_deg, double pitch_deg, double roll_deg);

/// Rotations from angles about the fixed x, y, z axes in radians, composed in the two orders box
/// formats use: R = Rz(rz)·Ry(ry)·Rx(rx) ("zyx": x applied first) and R = Rx(rx)·Ry(ry)·Rz(rz)
/// ("xyz", three.js Euler order "XYZ").
Eigen::Matrix3d rotation_zyx(const Eigen::Vector3d& rx_ry_rz);
Eigen::Matrix3d rotation_xyz(const Eigen::Vector3d& rx_ry_rz);
/// The inverses: (rx, ry, rz) in radians with rotation_zyx(result) == R (resp. rotation_xyz).
Eigen::Vector3d angles_zyx(const Eigen::Matrix3d& R);
Eigen::Vector3d angles_xyz(const Eigen::Matrix3d& R);

/// Pose from {x, y, z, yaw_deg, pitch_deg, roll_deg}.
Pose pose_from_xyz_ypr_deg(const std::array<double, 6>& xyz_ypr_deg);

/// Pose from a translation and a (not necessarily normalised) quaternion.
Pose pose_from_tq(const Eigen::Vector3d& t, const Eigen::Quaterniond& q);

/// Interpolation at fraction f in [0, 1]: translation linearly, rotation by slerp.
Pose interpolate(const Pose& a, const Pose& b, double f);

/// Interpolation along the geodesic of SE(3): a * exp(f * log(a^-1 * b)), the constant-velocity
/// screw motion from a to b. For planar robot poses it is the arc a differential drive follows
/// (not a straight chord, and not heading and position interpolated apart).
Pose interpolate_geodesic(const Pose& a, const Pose& b, double f);

/// An optical camera frame (x right, y down, z forward) in MRPT's camera frame (x forward, y left,
/// z up), the convention of MRPT sensor poses (rawlogs, the OLT plain-text layout, the Robot@Home
/// rig): T_robot_optical = T_robot_mrpt_camera * mrpt_camera_from_optical().
Pose mrpt_camera_from_optical();

/// The cross-product matrix: skew(v) * w == v.cross(w).
Eigen::Matrix3d skew(const Eigen::Vector3d& v);

/// Rotation angle of a pose in radians (0..pi).
double rotation_angle(const Pose& pose);

/// The rotation R minimising sum_k ||R R_P_k - R_Q_k||_F^2 over paired poses (orthogonal
/// Procrustes on the rotations).
Eigen::Matrix3d rotation_alignment(const std::vector<Pose>& P, const std::vector<Pose>& Q);

/// The rigid T bringing poses P onto Q: rotation_alignment, then the mean translation difference.
/// Unlike a fit of positions alone it is defined for a camera that only turns.
Pose pose_alignment(const std::vector<Pose>& P, const std::vector<Pose>& Q);

/// JSON form of a pose: [tx, ty, tz, qx, qy, qz, qw], the TUM order; qw >= 0.
nlohmann::json pose_to_json(const Pose& pose);
Pose pose_from_json(const nlohmann::json& value);

}  // namespace olt
