#pragma once
// Image reading and writing through OpenCV (and libpng for label images), with errors that name
// the file.
#include <opencv2/core.hpp>
#include <string>

#include "olt/core/fs.h"

namespace olt {

/// The largest image side read (pixels): a header claiming more is refused before any allocation.
inline constexpr int kMaxImageSide = 20000;

/// What a PNG's signature and IHDR chunk (its first 33 bytes) say.
struct PngHeader {
  int width = 0, height = 0;
  int bit_depth = 0;   ///< bits per sample
  int color_type = 0;  ///< PNG colour type: 0 grey, 2 RGB, 3 palette, 4 grey+alpha, 6 RGBA
  bool grey16() const { return bit_depth == 16 && color_type == 0; }
  std::string describe() const;  ///< "64x48 RGB, 8 bits per sample"
};

/// Reads the first 33 bytes of `file`; throws InputError naming the file when it is missing,
/// unreadable, not a PNG, or larger than kMaxImageSide on a side.
PngHeader read_png_header(const fs::path& file);

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
