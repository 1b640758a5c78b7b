#pragma once
// Image reading and writing through OpenCV (and libpng for label images), with errors that name
// the file.
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

/// PNG bytes of a 16-bit single-channel label image, encoded for speed (a third of encode_png's
/// time on label images, and smaller); any PNG reader reads it. Deterministic.
std::string encode_label_png(const cv::Mat& image);

/// JPEG bytes of an 8-bit image, for pictures meant for people (overlays, previews).
std::string encode_jpeg(const cv::Mat& image, int quality = 90);

}  // namespace olt
