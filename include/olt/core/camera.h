#pragma once
// Pinhole camera with OpenCV's Brown-Conrady distortion (k1 k2 p1 p2 k3).
#include <Eigen/Core>
#include <array>
#include <vector>

namespace olt {

struct Intrinsics {
  int width = 0;                          ///< image width, pixels
  int height = 0;                         ///< image height, pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< pixels
  std::array<double, 5> distortion{};     ///< k1 k2 p1 p2 k3

  bool distorted() const;
};

/// For every pixel (row-major), the undistorted normalised ray (x/z, y/z); a point at depth z is
/// (x*z, y*z, z) in the camera frame. Computed once per camera with cv::undistortPoints.
std::vector<Eigen::Vector2f> pixel_rays(const Intrinsics& camera);

/// Projects a camera-frame point to pixel coordinates (with distortion). False when z <= 0. With
/// `jacobian`, also d pixel / d p_camera.
bool project(const Intrinsics& camera, const Eigen::Vector3d& p_camera, Eigen::Vector2d* pixel,
             Eigen::Matrix<double, 2, 3>* jacobian = nullptr);

}  // namespace olt
