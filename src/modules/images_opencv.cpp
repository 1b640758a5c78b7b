// libolt_images.so: OpenCV's image codecs, and its undistortion (calib3d).
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "entry_points.h"

bool olt_image_encode(const cv::Mat& image, const std::string& extension, const std::vector<int>& params,
                      std::vector<unsigned char>& out) {
  try {
    return cv::imencode(extension, image, out, params);
  } catch (const cv::Exception&) {
    return false;
  }
}

void olt_image_decode(const std::string& bytes, int flags, cv::Mat& image, std::string& error) {
  const std::vector<unsigned char> buffer(bytes.begin(), bytes.end());
  try {
    image = cv::imdecode(buffer, flags);
  } catch (const cv::Exception& e) {
    image = cv::Mat();
    error = e.what();
  }
}

void olt_undistort_points(const std::vector<cv::Point2f>& pixels, const cv::Matx33d& K,
                          const std::vector<double>& distortion, std::vector<cv::Point2f>& normalised) {
  cv::undistortPoints(pixels, normalised, K, distortion, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 1e-9));
}
