#include "olt/core/image.h"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
// jpeglib.h needs FILE and size_t declared before it.
#include <jpeglib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <opencv2/imgcodecs.hpp>  // flags only: the codecs are behind image_codec()
#include <stdexcept>
#include <vector>

#include "olt/core/error.h"
#include "olt/core/image_codec.h"

namespace olt {
namespace {

// "BMP", "TIFF", "JPEG" or "image".
std::string format_of(const std::string& bytes) {
  if (bytes.rfind("BM", 0) == 0) return "BMP";
  if (bytes.rfind(std::string("II*\0", 4), 0) == 0 || bytes.rfind(std::string("MM\0*", 4), 0) == 0) return "TIFF";
  if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0xFF && static_cast<unsigned char>(bytes[1]) == 0xD8)
    return "JPEG";
  return "image";
}

cv::Mat decode(const std::string& file, const std::string& bytes, int flags) {
  const ImageCodec* codec = nullptr;
  try {
    codec = &image_codec();
  } catch (const std::runtime_error& e) {  // an installation without it (the olt:latest container)
    const std::string format = format_of(bytes);
    if (format == "image")  // not a format OpenCV would read either, most likely
      throw InputError(file,
                       "neither PNG nor JPEG (this installation of OLT reads other formats with "
                       "OpenCV's image codecs, which it does not have: " +
                           std::string(e.what()) + ")");
    throw InputError(file, "this " + format +
                               " needs OpenCV's image codecs, which this installation of OLT does not have "
                               "(PNG and plain JPEG are read without them; TIFF, BMP and JPEGs with EXIF, "
                               "CMYK or 12-bit samples need them; the container image olt:full has them): " +
                               e.what());
  }
  cv::Mat image;
  std::string error;
  codec->decode(bytes, flags, image, error);
  if (!error.empty()) throw InputError(file, "cannot decode image: " + error);
  if (image.empty()) throw InputError(file, "not an image OpenCV reads (PNG, JPEG, TIFF, BMP, ...)");
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

std::string ImageHeader::describe() const {
  return std::to_string(width) + "x" + std::to_string(height) + " " + format + ", " + std::to_string(channels) +
         (channels == 1 ? " channel, " : " channels, ") + std::to_string(bit_depth) + " bits per sample";
}

namespace {

void check_size(const fs::path& file, const ImageHeader& header) {
  if (header.width <= 0 || header.height <= 0 || header.width > kMaxImageSide || header.height > kMaxImageSide)
    throw InputError(file.string(), header.format + " header says " + std::to_string(header.width) + "x" +
                                        std::to_string(header.height) + "; images of 1 to " +
                                        std::to_string(kMaxImageSide) + " pixels a side are read");
}

// The signature and IHDR chunk (the first 33 bytes).
ImageHeader png_header(const fs::path& file, const std::string& head) {
  const auto* b = reinterpret_cast<const unsigned char*>(head.data());
  if (head.size() < 33 || std::memcmp(b + 12, "IHDR", 4) != 0)
    throw InputError(file.string(), "truncated PNG: no image header");
  auto u32 = [&](size_t at) {
    return (uint32_t{b[at]} << 24) | (uint32_t{b[at + 1]} << 16) | (uint32_t{b[at + 2]} << 8) | b[at + 3];
  };
  const int color = b[25];
  const int channels = color == PNG_COLOR_TYPE_GRAY         ? 1
                       : color == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                       : color == PNG_COLOR_TYPE_RGB_ALPHA  ? 4
                                                            : 3;
  const uint32_t width = u32(16), height = u32(20);
  ImageHeader header{"PNG", static_cast<int>(std::min<uint32_t>(width, INT32_MAX)),
                     static_cast<int>(std::min<uint32_t>(height, INT32_MAX)), channels, b[24]};
  check_size(file, header);
  return header;
}

struct JpegErrors {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void jpeg_fail(j_common_ptr info) {
  auto* errors = reinterpret_cast<JpegErrors*>(info->err);
  info->err->format_message(info, errors->message);
  std::longjmp(errors->jump, 1);
}

// libjpeg's own reading of the markers up to the frame header; "" on success, else its message
// (a header cut short: "Premature end of JPEG file" or similar).
std::string jpeg_header(const std::string& bytes, ImageHeader& header) {
  jpeg_decompress_struct info{};
  JpegErrors errors{};
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = jpeg_fail;
  errors.manager.output_message = [](j_common_ptr) {};
  // libjpeg reports errors by longjmp: nothing with a destructor is created below this point.
  if (setjmp(errors.jump)) {
    jpeg_destroy_decompress(&info);
    return errors.message[0] ? errors.message : "cannot read the JPEG header";
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&info, TRUE);
  header = {"JPEG", static_cast<int>(std::min<JDIMENSION>(info.image_width, INT32_MAX)),
            static_cast<int>(std::min<JDIMENSION>(info.image_height, INT32_MAX)), info.num_components,
            info.data_precision};
  jpeg_destroy_decompress(&info);
  return "";
}

bool is_jpeg(const std::string& bytes) {
  return bytes.size() >= 3 && static_cast<unsigned char>(bytes[0]) == 0xFF &&
         static_cast<unsigned char>(bytes[1]) == 0xD8 && static_cast<unsigned char>(bytes[2]) == 0xFF;
}

// Whether a marker libjpeg saved is an EXIF block (which may turn the picture: OpenCV applies its
// orientation).
bool has_exif(const jpeg_decompress_struct& info) {
  for (jpeg_saved_marker_ptr m = info.marker_list; m; m = m->next)
    if (m->marker == JPEG_APP0 + 1 && m->data_length >= 6 && std::memcmp(m->data, "Exif\0\0", 6) == 0) return true;
  return false;
}

// Decodes a grey or colour (YCbCr, RGB) JPEG without EXIF into 8-bit BGR with libjpeg-turbo, with the
// settings OpenCV's decoder uses (so the same pixels as cv::imdecode with IMREAD_COLOR); false,
// leaving `image` empty, for the JPEGs left to OpenCV (CMYK, EXIF, 12-bit); throws InputError when
// libjpeg cannot read the bytes. With `min_width` > 0, decoded at the smallest of libjpeg's DCT
// scales (1/2, 1/4, 1/8) that is still at least that wide.
bool decode_jpeg(const std::string& bytes, const std::string& name, cv::Mat& image, int min_width = 0) {
  jpeg_decompress_struct info{};
  JpegErrors errors{};
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = jpeg_fail;
  errors.manager.output_message = [](j_common_ptr) {};
  bool decoded = false;
  // libjpeg reports errors by longjmp: `image` (the only object with a destructor) exists before.
  if (setjmp(errors.jump)) {
    jpeg_destroy_decompress(&info);
    image.release();
    throw InputError(name, std::string("cannot decode JPEG: ") + errors.message);
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_save_markers(&info, JPEG_APP0 + 1, 0xFFFF);
  jpeg_read_header(&info, TRUE);
  if ((info.num_components == 1 || info.num_components == 3) && info.data_precision == 8 && !has_exif(info) &&
      info.image_width <= static_cast<JDIMENSION>(kMaxImageSide) &&
      info.image_height <= static_cast<JDIMENSION>(kMaxImageSide)) {
    info.out_color_space = JCS_EXT_BGR;
    info.scale_num = 1;
    for (unsigned denom = 8; denom > 1 && min_width > 0; denom /= 2)
      if ((info.image_width + denom - 1) / denom >= static_cast<JDIMENSION>(min_width)) {
        info.scale_denom = denom;
        break;
      }
    jpeg_start_decompress(&info);
    image.create(static_cast<int>(info.output_height), static_cast<int>(info.output_width), CV_8UC3);
    while (info.output_scanline < info.output_height) {
      JSAMPROW row = image.ptr<JSAMPLE>(static_cast<int>(info.output_scanline));
      jpeg_read_scanlines(&info, &row, 1);
    }
    jpeg_finish_decompress(&info);
    decoded = true;
  }
  jpeg_destroy_decompress(&info);
  return decoded;
}

int bits_of(int depth) {
  return depth == CV_8U || depth == CV_8S ? 8 : depth == CV_16U || depth == CV_16S ? 16 : depth == CV_64F ? 64 : 32;
}

}  // namespace

ImageHeader read_image_header(const fs::path& file) {
  // The frame header follows the metadata (EXIF, ICC profiles): the first 64 KB hold it in nearly
  // every JPEG; the whole file is read where they do not.
  // A PNG says all in its first 33 bytes: 10,000 frames cost 20,000 small reads, not 1.3 GB.
  const std::string start = read_file_head(file, 33);
  if (start.empty()) throw InputError(file.string(), "empty file (expected an image)");
  if (is_png(start)) return png_header(file, start);
  const std::string head = start.size() < 33 ? start : read_file_head(file, 65536);
  ImageHeader header;
  if (is_jpeg(head)) {
    std::string error = jpeg_header(head, header);
    if (!error.empty() && head.size() == 65536) error = jpeg_header(read_file(file), header);
    if (!error.empty()) throw InputError(file.string(), "cannot read the JPEG header: " + error);
    check_size(file, header);
    return header;
  }
  const std::string bytes = head.size() < 65536 ? head : read_file(file);
  const cv::Mat image = decode(file.string(), bytes, cv::IMREAD_UNCHANGED);
  header = {format_of(bytes), image.cols, image.rows, image.channels(), bits_of(image.depth())};
  check_size(file, header);
  return header;
}

cv::Mat read_grey16(const fs::path& file) { return decode_grey16(read_file(file), file.string()); }

cv::Mat decode_grey16(const std::string& bytes, const std::string& name) {
  cv::Mat image;
  if (!is_png(bytes)) {
    image = decode(name, bytes, cv::IMREAD_UNCHANGED);  // TIFF and the other formats
    if (image.type() != CV_16UC1)
      throw InputError(name, "expected a 16-bit single-channel image, found " + std::to_string(image.channels()) +
                                 " channel(s) of " + std::to_string(bits_of(image.depth())) + " bits");
    return image;
  }
  const std::string error = decode_png(bytes, true, image);
  if (!error.empty()) throw InputError(name, "cannot decode PNG: " + error);
  return image;
}

cv::Mat read_color(const fs::path& file) { return decode_color(read_file(file), file.string()); }

cv::Mat decode_color(const std::string& bytes, const std::string& name) { return decode_color_shrunk(bytes, name, 0); }

cv::Mat decode_color_shrunk(const std::string& bytes, const std::string& name, int min_width) {
  if (cv::Mat image; is_jpeg(bytes) && decode_jpeg(bytes, name, image, min_width)) return image;
  if (!is_png(bytes)) {  // TIFF, BMP, ... and the JPEGs decode_jpeg leaves to OpenCV
    cv::Mat image = decode(name, bytes, cv::IMREAD_COLOR);
    if (image.type() != CV_8UC3) image.convertTo(image, CV_8UC3);
    return image;
  }
  cv::Mat image;
  const std::string error = decode_png(bytes, false, image);
  if (!error.empty()) throw InputError(name, "cannot decode PNG: " + error);
  return image;
}

namespace {

// How a PNG is written: zlib level and strategy, and the row filter (libpng's adaptive choice when
// `filter` is 0).
struct PngWriting {
  int level;
  int strategy;
  int filter;
};

// PNG bytes of an 8- or 16-bit image of 1, 3 (BGR) or 4 (BGRA) channels, written by libpng with
// `how`: the same calls OpenCV's PNG encoder makes, so the same bytes as cv::imencode with the same
// settings (the golden digests of every shipped job's outputs check it).
std::string png_bytes(const cv::Mat& image, const PngWriting& how) {
  const int channels = image.channels();
  if ((image.depth() != CV_8U && image.depth() != CV_16U) || (channels != 1 && channels != 3 && channels != 4))
    throw std::invalid_argument("encode_png: expected an 8- or 16-bit image of 1, 3 or 4 channels");
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
  if (how.filter != 0) png_set_filter(png, PNG_FILTER_TYPE_BASE, how.filter);
  png_set_compression_level(png, how.level);
  png_set_compression_strategy(png, how.strategy);
  const int color = channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGBA;
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows),
               image.depth() == CV_8U ? 8 : 16, color, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE,
               PNG_FILTER_TYPE_BASE);
  png_write_info(png, info);
  png_set_bgr(png);   // OpenCV keeps colours as BGR(A)
  png_set_swap(png);  // PNG stores 16-bit samples big-endian
  for (int v = 0; v < image.rows; ++v) png_write_row(png, image.ptr<png_byte>(v));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

// libjpeg's output appended to a string, 16 KB at a time.
struct JpegSink {
  jpeg_destination_mgr manager;  // first: libjpeg sees the sink as its destination manager
  std::string* out;
  JOCTET buffer[16384];
};

void sink_start(j_compress_ptr info) {
  auto* sink = reinterpret_cast<JpegSink*>(info->dest);
  sink->manager.next_output_byte = sink->buffer;
  sink->manager.free_in_buffer = sizeof(sink->buffer);
}

boolean sink_full(j_compress_ptr info) {
  auto* sink = reinterpret_cast<JpegSink*>(info->dest);
  sink->out->append(reinterpret_cast<const char*>(sink->buffer), sizeof(sink->buffer));
  sink_start(info);
  return TRUE;
}

void sink_end(j_compress_ptr info) {
  auto* sink = reinterpret_cast<JpegSink*>(info->dest);
  sink->out->append(reinterpret_cast<const char*>(sink->buffer), sizeof(sink->buffer) - sink->manager.free_in_buffer);
}

}  // namespace

std::string encode_png(const cv::Mat& image) { return png_bytes(image, {3, Z_DEFAULT_STRATEGY, 0}); }

std::string encode_png_fast(const cv::Mat& image) { return png_bytes(image, {Z_BEST_SPEED, Z_RLE, PNG_FILTER_SUB}); }

std::string encode_picture_png(const cv::Mat& image) {
  return png_bytes(image, {3, Z_DEFAULT_STRATEGY, PNG_FILTER_UP});
}

namespace {

// JPEG bytes of `image` with OpenCV's settings; with `strips`, a restart marker after each row of MCUs.
std::string jpeg_bytes(const cv::Mat& image, int quality, bool strips) {
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw std::invalid_argument("encode_jpeg: expected an 8-bit grey or BGR image");
  std::string out;
  JpegSink sink{{}, &out, {}};
  sink.manager.init_destination = sink_start;
  sink.manager.empty_output_buffer = sink_full;
  sink.manager.term_destination = sink_end;
  jpeg_compress_struct info{};
  JpegErrors errors{};
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = jpeg_fail;
  // libjpeg reports errors by longjmp: nothing with a destructor is created below this point. The
  // settings are OpenCV's (cv::imencode with IMWRITE_JPEG_QUALITY): the same bytes.
  if (setjmp(errors.jump)) {
    jpeg_destroy_compress(&info);
    throw std::runtime_error(std::string("JPEG encoding failed: ") + errors.message);
  }
  jpeg_create_compress(&info);
  info.dest = &sink.manager;
  info.image_width = static_cast<JDIMENSION>(image.cols);
  info.image_height = static_cast<JDIMENSION>(image.rows);
  info.input_components = image.channels();
  info.in_color_space = image.channels() == 3 ? JCS_EXT_BGR : JCS_GRAYSCALE;  // libjpeg-turbo reads BGR itself
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, std::clamp(quality, 0, 100), TRUE);
  if (strips) info.restart_in_rows = 1;
  jpeg_start_compress(&info, TRUE);
  for (int v = 0; v < image.rows; ++v) {
    JSAMPROW row = const_cast<JSAMPROW>(image.ptr<JSAMPLE>(v));
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  return out;
}

}  // namespace

std::string encode_jpeg(const cv::Mat& image, int quality) { return jpeg_bytes(image, quality, false); }

std::string encode_jpeg_in_strips(const cv::Mat& image, int quality) { return jpeg_bytes(image, quality, true); }

int jpeg_strip_rows(int channels) { return channels == 3 ? 16 : 8; }

}  // namespace olt
