#pragma once
// Image reading and writing through OpenCV (libpng and libjpeg directly where speed or a header
// alone matters), with errors that name the file.
#include <opencv2/core.hpp>
#include <string>

#include "olt/core/fs.h"

namespace olt {

/// The largest image side read (pixels): a header claiming more is refused before any allocation.
inline constexpr int kMaxImageSide = 20000;

/// What an image file says of itself: read from the header alone for PNG and JPEG (the formats of
/// recordings), by decoding for the other formats OpenCV reads (TIFF, BMP, ...).
struct ImageHeader {
  std::string format;  ///< "PNG", "JPEG", "TIFF", "BMP" or "image"
  int width = 0, height = 0;
  int channels = 0;   ///< 1 grey, 2 grey+alpha, 3 colour, 4 colour+alpha
  int bit_depth = 0;  ///< bits per sample
  bool grey16() const { return bit_depth == 16 && channels == 1; }
  std::string describe() const;  ///< "64x48 JPEG, 3 channels, 8 bits per sample"
};

/// The header of an image file; throws InputError naming the file when it is missing, empty, not an
/// image OpenCV reads, or larger than kMaxImageSide on a side.
ImageHeader read_image_header(const fs::path& file);

/// Reads a 16-bit single-channel image (depth, label): PNG (through libpng), or TIFF or another
/// format OpenCV reads. Throws InputError naming the file when it is missing, not an image, or of
/// another type.
cv::Mat read_grey16(const fs::path& file);

/// read_grey16 of bytes already read; errors name `name`.
cv::Mat decode_grey16(const std::string& bytes, const std::string& name);

/// Reads a colour image of any format OpenCV decodes (PNG through libpng, JPEG through
/// libjpeg-turbo, TIFF, BMP, ...; 16-bit and grey images converted) as 8-bit BGR. Throws
/// InputError naming the file.
cv::Mat read_color(const fs::path& file);

/// read_color of bytes already read; errors name `name`.
cv::Mat decode_color(const std::string& bytes, const std::string& name);

/// decode_color for a picture that is to be shrunk to `min_width`: a JPEG is decoded at the smallest
/// of libjpeg's DCT scales (1/2, 1/4, 1/8 of its width, rounded up) still at least that wide, which
/// skips most of the decoding work; other formats, and `min_width` 0, are decoded whole.
cv::Mat decode_color_shrunk(const std::string& bytes, const std::string& name, int min_width);

/// PNG bytes of an 8- or 16-bit image of 1, 3 (BGR) or 4 (BGRA) channels (zlib level 3, libpng's
/// adaptive filters); deterministic, and the bytes cv::imencode gives with IMWRITE_PNG_COMPRESSION 3.
/// Written by libpng: OpenCV's codecs are not loaded.
std::string encode_png(const cv::Mat& image);

/// encode_png at zlib level 1 with the "sub" filter and run-length deflate, for drawings of flat
/// areas (maps): the bytes cv::imencode gives without parameters.
std::string encode_png_fast(const cv::Mat& image);

/// PNG bytes of a picture drawn for people (the report's scene and box pictures): zlib level 3 with
/// the "up" filter on every row. As small as encode_png's within a few percent (its adaptive filters
/// try every filter on every row), in 40-55 % of its time; the same pixels.
std::string encode_picture_png(const cv::Mat& image);

/// JPEG bytes of an 8-bit grey or BGR image, for pictures meant for people (overlays, previews):
/// libjpeg-turbo with OpenCV's settings (the bytes cv::imencode gives with IMWRITE_JPEG_QUALITY).
std::string encode_jpeg(const cv::Mat& image, int quality = 90);

/// encode_jpeg with a restart marker after each row of MCUs (jpeg_strip_rows(image.channels()) rows): the
/// same pixels decoded, and each strip's coded bytes depend on the strip's own rows alone, so a strip
/// can be encoded again by itself (splice_jpeg_strips in olt/core/image_strips.h).
std::string encode_jpeg_in_strips(const cv::Mat& image, int quality = 90);

/// The rows of a strip of encode_jpeg_in_strips of an image of `channels`: 16 for colour (chroma
/// halved both ways), 8 for grey.
int jpeg_strip_rows(int channels);

}  // namespace olt
