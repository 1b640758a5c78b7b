// Images as users have them: colour in any format OpenCV decodes, depth as 16-bit PNG or TIFF, and
// headers read without decoding where the format allows (PNG, JPEG), with errors naming the file.
#include "olt/core/image.h"

#include <catch2/catch.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "olt/core/error.h"
#include "olt/core/image_codec.h"
#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

std::string encoded(const cv::Mat& image, const std::string& extension, const std::vector<int>& params = {}) {
  std::vector<unsigned char> bytes;
  REQUIRE(olt::image_codec().encode(image, extension, params, bytes));
  return std::string(bytes.begin(), bytes.end());
}

// A colour image with structure (a gradient and a block), so a wrong decode shows.
cv::Mat pattern() {
  cv::Mat image(48, 64, CV_8UC3);
  for (int v = 0; v < image.rows; ++v)
    for (int u = 0; u < image.cols; ++u) image.at<cv::Vec3b>(v, u) = cv::Vec3b(u * 4, v * 5, (u + v) * 2);
  image(cv::Rect(10, 10, 20, 12)).setTo(cv::Scalar(0, 0, 255));
  return image;
}

}  // namespace

TEST_CASE("image headers: PNG, JPEG, BMP and TIFF give size, channels and bits") {
  TempDir dir;
  write_text(dir / "c.png", olt::encode_png(pattern()));
  write_text(dir / "c.jpg", encoded(pattern(), ".jpg"));
  write_text(dir / "c.bmp", encoded(pattern(), ".bmp"));
  write_text(dir / "d.tiff", encoded(cv::Mat(30, 40, CV_16UC1, cv::Scalar(1234)), ".tiff"));
  write_text(dir / "d.png", olt::encode_png(cv::Mat(30, 40, CV_16UC1, cv::Scalar(1234))));
  struct Expected {
    const char* file;
    const char* format;
    int width, height, channels, bits;
  };
  for (const Expected& e : {Expected{"c.png", "PNG", 64, 48, 3, 8}, Expected{"c.jpg", "JPEG", 64, 48, 3, 8},
                            Expected{"c.bmp", "BMP", 64, 48, 3, 8}, Expected{"d.tiff", "TIFF", 40, 30, 1, 16},
                            Expected{"d.png", "PNG", 40, 30, 1, 16}}) {
    INFO(e.file);
    const olt::ImageHeader h = olt::read_image_header(dir / e.file);
    CHECK(h.format == e.format);
    CHECK(h.width == e.width);
    CHECK(h.height == e.height);
    CHECK(h.channels == e.channels);
    CHECK(h.bit_depth == e.bits);
    CHECK(h.grey16() == (e.bits == 16 && e.channels == 1));
  }
}

TEST_CASE("a JPEG whose frame header follows 100 KB of metadata is still read from its header") {
  TempDir dir;
  const std::string jpeg = encoded(pattern(), ".jpg");
  // An APP15 segment holds at most 65533 bytes of data: two of them push the frame header past 64 KB.
  std::string segment = "\xFF\xEF";
  segment += static_cast<char>(0xFF);
  segment += static_cast<char>(0xFF);
  segment += std::string(65533, 'x');
  write_text(dir / "big.jpg", jpeg.substr(0, 2) + segment + segment + jpeg.substr(2));
  write_text(dir / "plain.jpg", jpeg);
  const olt::ImageHeader h = olt::read_image_header(dir / "big.jpg");
  CHECK(h.width == 64);
  CHECK(h.height == 48);
  CHECK(cv::norm(olt::read_color(dir / "big.jpg"), olt::read_color(dir / "plain.jpg"), cv::NORM_INF) == 0);
}

TEST_CASE("colour of any format decodes to the same 8-bit BGR pixels OpenCV gives - depth TIFF reads as PNG does") {
  TempDir dir;
  const cv::Mat original = pattern();
  write_text(dir / "c.png", olt::encode_png(original));
  write_text(dir / "c.bmp", encoded(original, ".bmp"));
  write_text(dir / "c.jpg", encoded(original, ".jpg", {1 /* IMWRITE_JPEG_QUALITY */, 100}));
  CHECK(cv::norm(olt::read_color(dir / "c.png"), original, cv::NORM_INF) == 0);  // lossless
  CHECK(cv::norm(olt::read_color(dir / "c.bmp"), original, cv::NORM_INF) == 0);
  const cv::Mat jpeg = olt::read_color(dir / "c.jpg");
  REQUIRE(jpeg.type() == CV_8UC3);
  CHECK(cv::norm(jpeg, original, cv::NORM_L1) / original.total() < 6);  // lossy, but the same picture

  cv::Mat depth(30, 40, CV_16UC1);
  cv::randu(depth, 0, 65535);
  write_text(dir / "d.tiff", encoded(depth, ".tiff"));
  CHECK(cv::norm(olt::read_grey16(dir / "d.tiff"), depth, cv::NORM_INF) == 0);
  write_text(dir / "d8.tiff", encoded(cv::Mat(30, 40, CV_8UC1, cv::Scalar(7)), ".tiff"));
  CHECK_THROWS_WITH(olt::read_grey16(dir / "d8.tiff"),
                    Catch::Contains("d8.tiff") && Catch::Contains("expected a 16-bit single-channel image"));
}

TEST_CASE("image files that are not images, cut short or empty are refused naming the file") {
  TempDir dir;
  write_text(dir / "text.jpg", "this is not an image\n");
  write_text(dir / "empty.png", "");
  write_text(dir / "cut.jpg", encoded(pattern(), ".jpg").substr(0, 40));
  CHECK_THROWS_WITH(olt::read_image_header(dir / "text.jpg"),
                    Catch::Contains("text.jpg") && Catch::Contains("not an image OpenCV reads"));
  CHECK_THROWS_WITH(olt::read_image_header(dir / "empty.png"), Catch::Contains("empty.png: empty file"));
  CHECK_THROWS_WITH(olt::read_image_header(dir / "cut.jpg"),
                    Catch::Contains("cut.jpg") && Catch::Contains("cannot read the JPEG header"));
  CHECK_THROWS_AS(olt::read_color(dir / "text.jpg"), olt::InputError);
}

TEST_CASE("PNG and JPEG are written with OpenCV's settings by libpng and libjpeg - the same bytes cv::imencode gives") {
  // OLT encodes without loading OpenCV's codecs (GDAL and ~130 libraries behind them); the files it
  // publishes must stay byte for byte what they were.
  cv::Mat grey(37, 53, CV_8UC1), deep(37, 53, CV_16UC1), bgra(37, 53, CV_8UC4);
  cv::RNG rng(7);
  rng.fill(grey, cv::RNG::UNIFORM, 0, 256);
  rng.fill(deep, cv::RNG::UNIFORM, 0, 65536);
  rng.fill(bgra, cv::RNG::UNIFORM, 0, 256);
  for (const cv::Mat& image : {pattern(), grey, deep, bgra}) {
    CHECK(olt::encode_png(image) == encoded(image, ".png", {cv::IMWRITE_PNG_COMPRESSION, 3}));
    CHECK(olt::encode_png_fast(image) == encoded(image, ".png"));
    // A picture's PNG: a filter of its own (OpenCV has no setting for it), the same pixels.
    cv::Mat decoded;
    std::string error;
    olt::image_codec().decode(olt::encode_picture_png(image), cv::IMREAD_UNCHANGED, decoded, error);
    REQUIRE(error.empty());
    CHECK(olt::encode_picture_png(image) != olt::encode_png(image));
    CHECK(decoded.type() == image.type());
    CHECK(cv::norm(decoded, image, cv::NORM_INF) == 0);
  }
  for (const cv::Mat& image : {pattern(), grey})
    for (int quality : {50, 90, 100})
      CHECK(olt::encode_jpeg(image, quality) == encoded(image, ".jpg", {cv::IMWRITE_JPEG_QUALITY, quality}));
  CHECK_THROWS_AS(olt::encode_png(cv::Mat(4, 4, CV_32FC1)), std::invalid_argument);
  CHECK_THROWS_AS(olt::encode_jpeg(bgra), std::invalid_argument);

  // Decoding: the JPEGs libjpeg-turbo decodes directly give OpenCV's pixels; one with an EXIF
  // orientation (the picture turned: OpenCV turns it back) is left to OpenCV.
  const std::string colour = olt::encode_jpeg(pattern(), 90), grey_jpeg = olt::encode_jpeg(grey, 90);
  auto opencv = [](const std::string& bytes) {
    cv::Mat image;
    std::string error;
    olt::image_codec().decode(bytes, cv::IMREAD_COLOR, image, error);
    return image;
  };
  CHECK(cv::norm(olt::decode_color(colour, "c.jpg"), opencv(colour), cv::NORM_INF) == 0);
  CHECK(cv::norm(olt::decode_color(grey_jpeg, "g.jpg"), opencv(grey_jpeg), cv::NORM_INF) == 0);
  // APP1 "Exif": a little-endian TIFF block with one entry, orientation (0x0112) = 6 (turned 90°).
  const unsigned char app1[] = {0xFF, 0xE1, 0,    34, 'E', 'x', 'i', 'f', 0, 0,              // marker, length, "Exif"
                                'I',  'I',  42,   0,  8,   0,   0,   0,                      // TIFF header: IFD at 8
                                1,    0,    0x12, 1,  3,   0,   1,   0,   0, 0, 6, 0, 0, 0,  // 1 entry: orientation 6
                                0,    0,    0,    0};                                        // no next IFD
  const std::string exif(reinterpret_cast<const char*>(app1), sizeof(app1));
  const std::string turned = colour.substr(0, 2) + exif + colour.substr(2);
  const cv::Mat upright = olt::decode_color(turned, "t.jpg");
  CHECK(upright.rows == pattern().cols);  // turned by OpenCV
  CHECK(cv::norm(upright, opencv(turned), cv::NORM_INF) == 0);
}

TEST_CASE("a JPEG decoded to be shrunk comes at the smallest DCT scale still as wide - the picture the same") {
  cv::Mat big;
  cv::resize(pattern(), big, cv::Size(640, 480), 0, 0, cv::INTER_LINEAR);  // 10x: smooth, as overlays are
  const std::string jpeg = olt::encode_jpeg(big, 90);
  // 640 wide: 1/2 is 320, 1/4 160, 1/8 80; the smallest of them at least `min_width` wide.
  CHECK(olt::decode_color_shrunk(jpeg, "o.jpg", 240).size() == cv::Size(320, 240));
  CHECK(olt::decode_color_shrunk(jpeg, "o.jpg", 160).size() == cv::Size(160, 120));
  CHECK(olt::decode_color_shrunk(jpeg, "o.jpg", 100).size() == cv::Size(160, 120));
  CHECK(olt::decode_color_shrunk(jpeg, "o.jpg", 80).size() == cv::Size(80, 60));
  CHECK(olt::decode_color_shrunk(jpeg, "o.jpg", 20).size() == cv::Size(80, 60));  // 1/8 at most
  CHECK(olt::decode_color_shrunk(jpeg, "o.jpg", 321).size() == cv::Size(640, 480));
  CHECK(olt::decode_color_shrunk(jpeg, "o.jpg", 0).size() == cv::Size(640, 480));
  // What a shrunk decode shows is what the whole decode shrunk shows: within a few levels per pixel.
  const cv::Mat half = olt::decode_color_shrunk(jpeg, "o.jpg", 240);
  cv::Mat whole_halved;
  cv::resize(olt::decode_color(jpeg, "o.jpg"), whole_halved, half.size(), 0, 0, cv::INTER_AREA);
  CHECK(cv::norm(half, whole_halved, cv::NORM_L1) / half.total() / 3 < 2.0);
  // Other formats are decoded whole.
  const std::string png = olt::encode_png(big);
  CHECK(olt::decode_color_shrunk(png, "o.png", 240).size() == cv::Size(640, 480));
  // An odd width rounds up: 641 at 1/2 is 321.
  cv::Mat odd;
  cv::resize(big, odd, cv::Size(641, 481));
  CHECK(olt::decode_color_shrunk(olt::encode_jpeg(odd, 90), "odd.jpg", 240).size() == cv::Size(321, 241));
}
