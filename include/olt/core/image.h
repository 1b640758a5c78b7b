#pragma once
// PNG reading and writing through OpenCV, with errors that name the file.
#include <opencv2/core.hpp>
#include <string>

#include "olt/core/fs.h"

namespace olt {

/// Reads a 16-bit single-channel PNG (depth or label image). Throws InputError naming the file
/// when it is missing, not a PNG, or of another type.
cv::Mat read_png_u16(const fs::path& file);

/// Reads a colour image as 8-bit BGR. Throws InputError naming the file.
cv::Mat read_png_bgr(const fs::path& file);

/// PNG bytes of an 8-bit (1 or 3 channel) or 16-bit single-channel image; deterministic.
std::string encode_png(const cv::Mat& image);

}  // namespace olt
