// libolt_images.so: OpenCV's image codecs (imgcodecs, and GDAL and ~130 libraries behind it), for the
// images libpng and libjpeg-turbo do not read directly.
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
