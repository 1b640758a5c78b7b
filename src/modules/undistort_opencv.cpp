// libolt_undistort.so: OpenCV's undistortion (calib3d, ~25 libraries, 4 ms to load), apart from the
// image codecs (~130 libraries, 70-90 ms): a run on a camera with lens distortion loads only this.
#include <opencv2/calib3d.hpp>

#include "entry_points.h"

void olt_undistort_points(const std::vector<cv::Point2f>& pixels, const cv::Matx33d& K,
                          const std::vector<double>& distortion, std::vector<cv::Point2f>& normalised) {
  cv::undistortPoints(pixels, normalised, K, distortion, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 1e-9));
}
