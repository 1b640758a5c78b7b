#pragma once
// The colour term of RGB-D registration: intensities of the source's pixels, seen from their depth,
// compared with the target's colour image where the source pose puts them (direct image alignment,
// as in dense RGB-D odometry, Kerl et al. ICRA 2013). Optional beside the geometric term.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "olt/core/camera.h"
#include "olt/core/geometry.h"

namespace olt {

/// A colour image as grey intensities in [0, 1], smoothed and reduced to 1/`scale` of its
/// resolution, with its gradients (per pixel of the reduced image).
struct IntensityImage {
  cv::Mat intensity, gradient_x, gradient_y;  ///< CV_32F
  Intrinsics camera;                          ///< the full-resolution camera
  int scale = 1;                              ///< full-resolution pixels per reduced pixel

  /// Where the camera-frame point `p` falls in the reduced image; false behind the camera.
  bool pixel(const Eigen::Vector3d& p, Eigen::Vector2d* uv) const;
};

/// `bgr` (8-bit, 3 channels) or grey; `scale` 1, 2 or 4.
IntensityImage make_intensity_image(const cv::Mat& bgr, const Intrinsics& camera, int scale);

/// Bilinear sample at a reduced-image position; false where the 2x2 neighbourhood leaves the image.
bool sample(const cv::Mat& image, const Eigen::Vector2d& uv, float* value);

/// Source pixels for the colour term: depth points (in the depth camera frame) whose projection in
/// the colour image has a gradient of at least `min_gradient` per reduced pixel, with the
/// intensity seen there.
struct PhotometricPoints {
  std::vector<Eigen::Vector3d> points;  ///< depth camera frame, metres
  std::vector<float> intensities;
};

PhotometricPoints select_photometric_points(const std::vector<Eigen::Vector3d>& depth_points,
                                            const IntensityImage& image, const Pose& T_color_depth,
                                            double min_gradient);

/// The colour term of one registration: the source's points and the target's image, placed by
/// `T_color_world` (world to the target's colour camera). Residual: target intensity at the
/// point's projection minus its own intensity, Huber-weighted beyond `huber`; each squared
/// residual counts `weight` times against the geometric term's Mahalanobis distances.
struct PhotometricTerm {
  const PhotometricPoints* source = nullptr;
  const IntensityImage* target = nullptr;
  Pose T_color_world = Pose::Identity();
  double weight = 0;
  double huber = 0.2;
};

}  // namespace olt
