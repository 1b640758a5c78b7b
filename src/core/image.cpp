#include "olt/core/image.h"

#include <png.h>
#include <zlib.h>

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
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

void append_bytes(png_structp png, png_bytep data, png_size_t size) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), size);
}

void no_flush(png_structp) {}

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

std::string encode_label_png(const cv::Mat& image) {
  if (image.type() != CV_16UC1) throw std::invalid_argument("encode_label_png: expected a 16-bit single-channel image");
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("PNG encoding failed: out of memory");
  }
  // libpng reports errors by longjmp: nothing with a destructor is created below this point.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("PNG encoding failed");
  }
  png_set_write_fn(png, &out, append_bytes, no_flush);
  // Label images are long runs that repeat from row to row: the "up" filter turns them into
  // zeros and run-length deflate at level 1 packs those, 3x faster than libpng's adaptive filters
  // and smaller.
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  png_set_compression_level(png, 1);
  png_set_compression_strategy(png, Z_RLE);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), 16,
               PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  png_write_info(png, info);
  png_set_swap(png);  // PNG stores 16-bit samples big-endian
  for (int v = 0; v < image.rows; ++v) png_write_row(png, image.ptr<png_byte>(v));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

std::string encode_jpeg(const cv::Mat& image, int quality) {
  std::vector<uchar> buffer;
  if (!cv::imencode(".jpg", image, buffer, {cv::IMWRITE_JPEG_QUALITY, quality}))
    throw std::runtime_error("JPEG encoding failed");
  return std::string(buffer.begin(), buffer.end());
}

}  // namespace olt
