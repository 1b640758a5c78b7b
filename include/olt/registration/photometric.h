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

/// A colour image as grey intensities in [0, 1], halved `halvings` times (cv::pyrDown) and
/// smoothed, with its gradients in intensity per reduced pixel.
struct IntensityImage {
  cv::Mat intensity, gradient_x, gradient_y;  ///< CV_32FC1, the reduced size
  Intrinsics camera;                          ///< the full-resolution camera
  int scale = 1;                              ///< full-resolution pixels per reduced pixel: 2^halvings

  /// Where the camera-frame point `p` falls in the reduced image; false behind the camera. With
  /// `jacobian`, also d uv / d p.
  bool pixel(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* jacobian = nullptr) const;
};

/// `image`: 8-bit BGR or grey (anything else throws std::invalid_argument); `halvings` 0 to 4.
IntensityImage make_intensity_image(const cv::Mat& image, const Intrinsics& camera, int halvings);

/// Bilinear sample of a CV_32FC1 image at a reduced-image position; false where the 2x2
/// neighbourhood leaves the image.
bool sample(const cv::Mat& image, const Eigen::Vector2d& uv, float* value);

/// Source pixels for the colour term, with the intensity seen at each.
struct PhotometricPoints {
  std::vector<Eigen::Vector3d> points;  ///< depth camera frame, metres
  std::vector<float> intensities;       ///< in [0, 1], from the source's IntensityImage
};

/// The depth points (depth camera frame) whose projection in the colour image has a gradient of
/// at least `min_gradient` (intensity per reduced pixel).
PhotometricPoints select_photometric_points(const std::vector<Eigen::Vector3d>& depth_points,
                                            const IntensityImage& image, const Pose& T_color_depth,
                                            double min_gradient);

/// The colour term of one registration: the source's points and the target's image, placed by
/// `T_color_world` (world to the target's colour camera). Residual: target intensity at the
/// point's projection minus its own intensity. Each squared residual counts `weight` times
/// against one geometric correspondence's Mahalanobis distance, Huber-weighted beyond `huber`.
struct PhotometricTerm {
  const PhotometricPoints* source = nullptr;
  const IntensityImage* target = nullptr;
  Pose T_color_world = Pose::Identity();
  double weight = 0;  ///< dimensionless (RegistrationPosesConfig::photometric_weight)
  double huber = 0;   ///< intensity in [0, 1] (RegistrationPosesConfig::photometric_huber)
};

}  // namespace olt
