#include "olt/core/image.h"

#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "olt/core/error.h"

namespace olt {
namespace {

cv::Mat decode(const fs::path& file, int flags) {
  const std::string bytes = read_file(file);
  const std::vector<uchar> buffer(bytes.begin(), bytes.end());
  cv::Mat image;
  try {
    image = cv::imdecode(buffer, flags);
  } catch (const cv::Exception& e) {
    throw InputError(file.string(), std::string("cannot decode image: ") + e.what());
  }
  if (image.empty()) throw InputError(file.string(), "not a readable image (expected PNG)");
  return image;
}

}  // namespace

cv::Mat read_png_u16(const fs::path& file) {
  cv::Mat image = decode(file, cv::IMREAD_UNCHANGED);
  if (image.type() != CV_16UC1)
    throw InputError(file.string(), "expected a 16-bit single-channel PNG, found " + std::to_string(image.channels()) +
                                        " channel(s) of " + std::to_string(8 * image.elemSize1()) + " bits");
  return image;
}

cv::Mat read_png_bgr(const fs::path& file) { return decode(file, cv::IMREAD_COLOR); }

std::string encode_png(const cv::Mat& image) {
  std::vector<uchar> buffer;
  if (!cv::imencode(".png", image, buffer, {cv::IMWRITE_PNG_COMPRESSION, 3}))
    throw std::runtime_error("PNG encoding failed");
  return std::string(buffer.begin(), buffer.end());
}

}  // namespace olt
