#pragma once
// OpenCV's calib3d (cv::undistortPoints), needed only for cameras with lens distortion, reached
// through this table like the image codecs (olt/core/image_codec.h): the `olt` binary loads its own
// small module (libolt_undistort.so, ~4 ms) on first use, so a run of undistorted cameras, or one with
// nothing to do, does not load calib3d and the libraries behind it (features2d, flann), and a
// distorted camera's does not load the image codecs.
#include <opencv2/core.hpp>
#include <vector>

namespace olt {

struct Undistorter {
  /// cv::undistortPoints of `pixels` with camera matrix K and distortion k1 k2 p1 p2 k3, iterated to
  /// convergence: normalised image coordinates.
  void (*points)(const std::vector<cv::Point2f>& pixels, const cv::Matx33d& K, const std::vector<double>& distortion,
                 std::vector<cv::Point2f>& normalised);
};

/// The table; throws std::runtime_error naming the module when it cannot be loaded.
const Undistorter& undistorter();

}  // namespace olt
