// Images as users have them: colour in any format OpenCV decodes, depth as 16-bit PNG or TIFF, and
// headers read without decoding where the format allows (PNG, JPEG), with errors naming the file.
#include "olt/core/image.h"

#include <catch2/catch.hpp>
#include <opencv2/core.hpp>

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
