#pragma once
// OpenCV's image codecs (imgcodecs), the heaviest library OLT uses (GDAL and ~130 shared libraries
// load behind it, ~125 ms to load), reached through this table: the `olt` binary loads it on first use
// (src/modules/lazy.cpp), which is only to decode images that are not PNG (JPEG colour, TIFF, BMP,
// ...): PNG is read and PNG and JPEG are written by libpng and libjpeg-turbo directly
// (olt/core/image.h), so a run on PNG recordings, or an edit's relabel, never loads it. Tests link it
// directly (src/modules/linked.cpp).
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace olt {

struct ImageCodec {
  /// cv::imencode: false when OpenCV cannot encode the image with `extension` (".png", ".jpg").
  bool (*encode)(const cv::Mat& image, const std::string& extension, const std::vector<int>& params,
                 std::vector<unsigned char>& out);
  /// cv::imdecode into `image` (empty when the bytes are no image OpenCV reads); OpenCV's own
  /// error, if it raised one, in `error`.
  void (*decode)(const std::string& bytes, int flags, cv::Mat& image, std::string& error);
};

/// The codec table; throws std::runtime_error naming the module and where it was looked for when it
/// cannot be loaded.
const ImageCodec& image_codec();

}  // namespace olt
