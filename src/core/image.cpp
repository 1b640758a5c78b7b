#include "olt/core/image.h"

#include <png.h>
#include <zlib.h>

#include <cstdio>
#include <cstring>
#include <opencv2/imgcodecs.hpp>  // flags only: the codecs are behind image_codec()
#include <stdexcept>
#include <vector>

#include "olt/core/error.h"
#include "olt/core/image_codec.h"

namespace olt {
namespace {

cv::Mat decode(const std::string& file, const std::string& bytes, int flags) {
  cv::Mat image;
  std::string error;
  image_codec().decode(bytes, flags, image, error);
  if (!error.empty()) throw InputError(file, "cannot decode image: " + error);
  if (image.empty()) throw InputError(file, "not a readable image (expected PNG)");
  return image;
}

const char* color_type_name(int color) {
  return color == PNG_COLOR_TYPE_GRAY         ? "grey"
         : color == PNG_COLOR_TYPE_RGB        ? "RGB"
         : color == PNG_COLOR_TYPE_PALETTE    ? "palette"
         : color == PNG_COLOR_TYPE_GRAY_ALPHA ? "grey+alpha"
                                              : "RGBA";
}

struct PngSource {
  const std::string* bytes;
  size_t at;
};

void read_bytes(png_structp png, png_bytep data, png_size_t size) {
  auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
  if (source->bytes->size() - source->at < size) png_error(png, "file is truncated");
  std::memcpy(data, source->bytes->data() + source->at, size);
  source->at += size;
}

void keep_message(png_structp png, png_const_charp message) {
  std::strncpy(static_cast<char*>(png_get_error_ptr(png)), message, 255);
  png_longjmp(png, 1);
}

void ignore_warning(png_structp, png_const_charp) {}

// Decodes PNG bytes with libpng into 16-bit grey (`sixteen_bit`) or 8-bit BGR, converting any other
// colour type; "" on success, else libpng's message. The zlib Adler-32 of the image data is not
// checked: each chunk's CRC-32, which libpng does check, already covers the same bytes, and Adler-32
// was a tenth of the labeling's time.
std::string decode_png(const std::string& bytes, bool sixteen_bit, cv::Mat& image) {
  char message[256] = "out of memory";
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, message, keep_message, ignore_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return message;
  }
  PngSource source{&bytes, 0};
  std::vector<png_bytep> rows;
  // libpng reports errors by longjmp: everything with a destructor exists before this point.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return message[0] ? message : "cannot decode";
  }
  png_set_read_fn(png, &source, read_bytes);
#ifdef PNG_IGNORE_ADLER32
  png_set_option(png, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
#endif
  png_read_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  const int bit_depth = png_get_bit_depth(png, info), color = png_get_color_type(png, info);
  if (sixteen_bit) {
    if (color != PNG_COLOR_TYPE_GRAY || bit_depth != 16) {
      const char* kind = color_type_name(color);
      std::snprintf(message, sizeof message, "expected a 16-bit single-channel PNG, found %s with %d bits per sample",
                    kind, bit_depth);
      png_error(png, message);
    }
    png_set_swap(png);  // PNG stores 16-bit samples big-endian
  } else {
    if (bit_depth == 16) png_set_strip_16(png);
    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (color == PNG_COLOR_TYPE_GRAY || color == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
    if (color & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(png);
    png_set_bgr(png);
  }
  if (png_get_interlace_type(png, info) != PNG_INTERLACE_NONE) png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (width > static_cast<png_uint_32>(kMaxImageSide) || height > static_cast<png_uint_32>(kMaxImageSide) ||
      png_get_rowbytes(png, info) != width * (sixteen_bit ? 2u : 3u))
    png_error(png, "unsupported image layout");
  image.create(static_cast<int>(height), static_cast<int>(width), sixteen_bit ? CV_16UC1 : CV_8UC3);
  rows.resize(height);
  for (png_uint_32 v = 0; v < height; ++v) rows[v] = image.ptr<png_byte>(static_cast<int>(v));
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return "";
}

bool is_png(const std::string& bytes) {
  return bytes.size() >= 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) == 0;
}

void append_bytes(png_structp png, png_bytep data, png_size_t size) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), size);
}

void no_flush(png_structp) {}

}  // namespace

std::string PngHeader::describe() const {
  return std::to_string(width) + "x" + std::to_string(height) + " " + color_type_name(color_type) + ", " +
         std::to_string(bit_depth) + " bits per sample";
}

PngHeader read_png_header(const fs::path& file) {
  std::string bytes = read_file_head(file, 33);
  if (bytes.empty()) throw InputError(file.string(), "empty file (expected a PNG image)");
  if (!is_png(bytes)) throw InputError(file.string(), "not a PNG image");
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 33 || std::memcmp(b + 12, "IHDR", 4) != 0)
    throw InputError(file.string(), "truncated PNG: no image header");
  auto u32 = [&](size_t at) {
    return (uint32_t{b[at]} << 24) | (uint32_t{b[at + 1]} << 16) | (uint32_t{b[at + 2]} << 8) | b[at + 3];
  };
  const uint32_t width = u32(16), height = u32(20);
  if (width == 0 || height == 0 || width > static_cast<uint32_t>(kMaxImageSide) ||
      height > static_cast<uint32_t>(kMaxImageSide))
    throw InputError(file.string(), "PNG header says " + std::to_string(width) + "x" + std::to_string(height) +
                                        "; images of 1 to " + std::to_string(kMaxImageSide) +
                                        " pixels a side are read");
  return {static_cast<int>(width), static_cast<int>(height), b[24], b[25]};
}

cv::Mat read_png_u16(const fs::path& file) {
  const std::string bytes = read_file(file);
  if (!is_png(bytes)) throw InputError(file.string(), "not a PNG file (expected a 16-bit single-channel PNG)");
  cv::Mat image;
  const std::string error = decode_png(bytes, true, image);
  if (!error.empty()) throw InputError(file.string(), "cannot decode PNG: " + error);
  return image;
}

cv::Mat read_png_bgr(const fs::path& file) {
  const std::string bytes = read_file(file);
  if (!is_png(bytes)) return decode(file.string(), bytes, cv::IMREAD_COLOR);  // JPEG and the other formats
  cv::Mat image;
  const std::string error = decode_png(bytes, false, image);
  if (!error.empty()) throw InputError(file.string(), "cannot decode PNG: " + error);
  return image;
}

std::string encode_png(const cv::Mat& image) {
  std::vector<uchar> buffer;
  if (!image_codec().encode(image, ".png", {cv::IMWRITE_PNG_COMPRESSION, 3}, buffer))
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
  if (!image_codec().encode(image, ".jpg", {cv::IMWRITE_JPEG_QUALITY, quality}, buffer))
    throw std::runtime_error("JPEG encoding failed");
  return std::string(buffer.begin(), buffer.end());
}

}  // namespace olt
