#pragma once
// OpenCV's image codecs (imgcodecs), the heaviest library OLT uses (GDAL and ~130 shared libraries
// load behind it), reached through this table: the `olt` binary loads it on first use
// (src/modules/lazy.cpp), so commands that write no JPEG start in tens of milliseconds; tests link
// it directly (src/modules/linked.cpp).
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
