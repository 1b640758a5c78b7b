// Images coded in strips (label PNGs in bands, overlay JPEGs with a restart marker per row of MCUs):
// any reader reads them, and an image spliced from its previous bytes where rows changed is byte for
// byte the image encoded whole.
#include "olt/core/image_strips.h"

#include <zlib.h>

#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "olt/core/image.h"
#include "olt/core/image_codec.h"

namespace {

// A label image as labeling makes them: runs of a few ids, some rows repeating the one above.
cv::Mat labels(int rows, int cols, uint64_t seed) {
  cv::Mat image(rows, cols, CV_16UC1, cv::Scalar(0));
  cv::RNG rng(seed);
  for (int k = 0; k < 12; ++k) {
    const int x = rng.uniform(0, cols), y = rng.uniform(0, rows);
    const cv::Rect r(x, y, rng.uniform(1, cols - x + 1), rng.uniform(1, rows - y + 1));
    image(r).setTo(rng.uniform(1, 70000));
  }
  for (int v = 0; v < rows; v += 7) image.at<uint16_t>(v, rng.uniform(0, cols)) = 65535;  // no depth
  return image;
}

cv::Mat photo(int rows, int cols, int channels) {  // smooth with texture, as overlays are
  cv::Mat image(rows, cols, CV_8UC(channels));
  cv::RNG rng(3);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(image, image, cv::Size(5, 5), 2);
  return image;
}

cv::Mat opencv_decoded(const std::string& bytes, int flags) {
  cv::Mat image;
  std::string error;
  olt::image_codec().decode(bytes, flags, image, error);
  REQUIRE(error.empty());
  return image;
}

bool same_pixels(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

std::vector<bool> rows_of(const cv::Mat& a, const cv::Mat& b) {  // the rows that differ
  std::vector<bool> changed(static_cast<size_t>(a.rows));
  for (int v = 0; v < a.rows; ++v) changed[static_cast<size_t>(v)] = cv::norm(a.row(v), b.row(v), cv::NORM_INF) != 0;
  return changed;
}

}  // namespace

TEST_CASE("a label PNG in bands reads back as its labels, in OLT and in OpenCV") {
  for (const auto& [rows, cols] :
       std::vector<std::pair<int, int>>{{1, 1}, {31, 5}, {32, 64}, {33, 64}, {65, 17}, {480, 640}}) {
    const cv::Mat image = labels(rows, cols, static_cast<uint64_t>(rows * 1000 + cols));
    const std::string png = olt::encode_label_png(image);
    CHECK(same_pixels(olt::decode_grey16(png, "labels.png"), image));
    CHECK(same_pixels(opencv_decoded(png, cv::IMREAD_UNCHANGED), image));
    CHECK(olt::encode_label_png(image) == png);  // deterministic
  }
  CHECK_THROWS_AS(olt::encode_label_png(cv::Mat(4, 4, CV_8UC1)), std::invalid_argument);
  CHECK_THROWS_AS(olt::encode_label_png(cv::Mat()), std::invalid_argument);
}

TEST_CASE("the rows a label PNG's splice reads: the bands of the rows flagged, each with the row above it") {
  const auto read_rows = [](std::vector<int> flagged, int height) {
    std::vector<bool> rows(static_cast<size_t>(height), false);
    for (int v : flagged) rows[static_cast<size_t>(v)] = true;
    std::vector<int> read;
    const std::vector<bool> flags = olt::label_png_rows_read(rows);
    REQUIRE(flags.size() == rows.size());
    for (int v = 0; v < height; ++v)
      if (flags[static_cast<size_t>(v)]) read.push_back(v);
    return read;
  };
  const auto range = [](int first, int last) {
    std::vector<int> v;
    for (int r = first; r < last; ++r) v.push_back(r);
    return v;
  };
  CHECK(read_rows({}, 100).empty());
  CHECK(read_rows({40}, 100) == range(31, 64));  // band 1 (rows 32-63) and the row above it
  CHECK(read_rows({32}, 100) == range(31, 64));
  CHECK(read_rows({31}, 100) == range(0, 64));  // band 0's last row: the row above band 1 too
  CHECK(read_rows({0}, 100) == range(0, 32));
  CHECK(read_rows({99}, 100) == range(95, 100));  // the last band, short
  CHECK(read_rows({5, 70}, 100) == [&] {
    auto v = range(0, 32);
    for (int r : range(63, 96)) v.push_back(r);
    return v;
  }());
}

TEST_CASE("a label PNG spliced where rows changed is the PNG encoded whole") {
  const cv::Mat before = labels(480, 640, 11);
  const std::string before_png = olt::encode_label_png(before);
  const auto spliced_is_whole = [&](const cv::Mat& now) {
    const std::string spliced = olt::splice_label_png(before_png, before, now);
    CHECK(spliced == olt::encode_label_png(now));
    CHECK(same_pixels(olt::decode_grey16(spliced, "now.png"), now));
    // Told that every row differs, or told nothing usable (flags of another length): the same bytes.
    CHECK(olt::splice_label_png(before_png, before, now, std::vector<bool>(static_cast<size_t>(now.rows), true)) ==
          spliced);
    CHECK(olt::splice_label_png(before_png, before, now, std::vector<bool>(3, false)) == spliced);
    // Of the image before, only the rows label_png_rows_read flags are read: other labels in the rest
    // give the same bytes.
    const std::vector<bool> changed = olt::differing_rows(now, before);
    const std::vector<bool> read = olt::label_png_rows_read(changed);
    cv::Mat partly = before.clone();
    for (int v = 0; v < partly.rows; ++v)
      if (!read[static_cast<size_t>(v)]) partly.row(v).setTo(0xBEEF);
    CHECK(olt::splice_label_png(before_png, partly, now, changed) == spliced);
  };
  SECTION("a box's rectangle") {
    cv::Mat now = before.clone();
    now(cv::Rect(100, 150, 80, 60)).setTo(42);
    spliced_is_whole(now);
  }
  SECTION("one pixel on each side of a band's edge: the last row of a band, the first of the next") {
    for (int v : {0, 31, 32, 63, 64, 479}) {
      cv::Mat now = before.clone();
      now.at<uint16_t>(v, 320) ^= 0x0101;
      spliced_is_whole(now);
    }
  }
  SECTION("every pixel") { spliced_is_whole(labels(480, 640, 12)); }
  SECTION("two thirds of the bands, and one more: the same bytes either way") {
    for (int bands : {10, 11}) {  // of 15
      cv::Mat now = before.clone();
      for (int band = 0; band < bands; ++band) now.at<uint16_t>(band * 32 + 5, 7) ^= 0x0101;
      spliced_is_whole(now);
    }
  }
  SECTION("nothing: the same bytes") { CHECK(olt::splice_label_png(before_png, before, before) == before_png); }
  SECTION("bytes that are not such a PNG, or labels of another size: encoded whole") {
    const cv::Mat now = labels(480, 640, 13);
    const std::string whole = olt::encode_label_png(now);
    CHECK(olt::splice_label_png("", before, now) == whole);
    CHECK(olt::splice_label_png(before_png.substr(0, before_png.size() - 20), before, now) == whole);
    CHECK(olt::splice_label_png(olt::encode_png(before), before, now) == whole);
    CHECK(olt::splice_label_png(olt::encode_label_png(before.rowRange(0, 479)), before.rowRange(0, 479), now) == whole);
  }
}

TEST_CASE("adler-32 mended for bytes replaced is zlib's checksum of the new bytes") {
  cv::RNG rng(5);
  for (size_t length : {size_t{1}, size_t{1000}, size_t{200000}}) {
    std::string bytes(length, '\0');
    for (char& c : bytes) c = static_cast<char>(rng.uniform(0, 256));
    const auto adler = [](const std::string& s) {
      return static_cast<uint32_t>(
          adler32(adler32(0, nullptr, 0), reinterpret_cast<const Bytef*>(s.data()), static_cast<uInt>(s.size())));
    };
    for (int k = 0; k < 5; ++k) {
      const size_t offset = static_cast<size_t>(rng.uniform(0, static_cast<int>(length)));
      const size_t size = static_cast<size_t>(rng.uniform(0, static_cast<int>(length - offset) + 1));
      std::string now = bytes;
      for (size_t j = offset; j < offset + size; ++j) now[j] = static_cast<char>(rng.uniform(0, 256));
      CHECK(olt::adler32_replaced(adler(bytes), length, offset, bytes.substr(offset, size), now.substr(offset, size)) ==
            adler(now));
    }
  }
  CHECK_THROWS_AS(olt::adler32_replaced(1, 10, 8, "abc", "abd"), std::invalid_argument);
  CHECK_THROWS_AS(olt::adler32_replaced(1, 10, 0, "abc", "ab"), std::invalid_argument);
}

TEST_CASE("a JPEG in strips decodes as the JPEG encoded whole, and spliced where rows changed is it encoded whole") {
  for (const cv::Mat& before : {photo(480, 640, 3), photo(53, 70, 3), photo(37, 29, 1)}) {
    const int strip = olt::jpeg_strip_rows(before.channels());
    const std::string before_jpg = olt::encode_jpeg_in_strips(before);
    CHECK(same_pixels(olt::decode_color(before_jpg, "strips.jpg"),
                      olt::decode_color(olt::encode_jpeg(before), "whole.jpg")));
    cv::Mat now = before.clone();
    cv::line(now, {3, before.rows / 2}, {before.cols - 5, before.rows / 2 + strip}, cv::Scalar(0, 255, 0), 1,
             cv::LINE_AA);
    now.row(before.rows - 1).setTo(7);  // the last strip, which may be short
    const std::string whole = olt::encode_jpeg_in_strips(now);
    CHECK(olt::splice_jpeg_strips(before_jpg, now, rows_of(before, now)) == whole);
    CHECK(olt::splice_jpeg_strips(before_jpg, before, std::vector<bool>(before.rows, false)) == before_jpg);
    // Rows said to have changed that did not: encoded again, the same bytes.
    CHECK(olt::splice_jpeg_strips(before_jpg, before, std::vector<bool>(before.rows, true)) == before_jpg);
    // Not such a JPEG, or the rows' flags not one per row: not spliced (the caller draws it whole).
    CHECK_FALSE(olt::splice_jpeg_strips(olt::encode_jpeg(before), now, rows_of(before, now)));
    CHECK_FALSE(olt::splice_jpeg_strips(before_jpg.substr(0, before_jpg.size() - 1), now, rows_of(before, now)));
    CHECK_FALSE(olt::splice_jpeg_strips(before_jpg, now, {}));
  }
  // Another size's bytes, or another number of channels'.
  const cv::Mat small = photo(48, 64, 3), large = photo(64, 64, 3), grey = photo(8, 64, 1), colour = photo(8, 64, 3);
  CHECK_FALSE(olt::splice_jpeg_strips(olt::encode_jpeg_in_strips(small), large, std::vector<bool>(64, false)));
  CHECK_FALSE(olt::splice_jpeg_strips(olt::encode_jpeg_in_strips(colour), grey, std::vector<bool>(8, false)));
}

TEST_CASE("a picture redrawn in strips: only its changed strips drawn where the bytes before are its strips") {
  const cv::Mat before = photo(53, 70, 3);
  cv::Mat now = before.clone();
  now.row(20).setTo(200);
  int drawn_rows = 0;
  const auto draw = [&](const std::vector<bool>& rows) {  // the rows flagged (every row for none), others black
    cv::Mat drawn(now.size(), now.type(), cv::Scalar::all(0));
    for (int v = 0; v < now.rows; ++v)
      if (rows.empty() || rows[static_cast<size_t>(v)]) {
        now.row(v).copyTo(drawn.row(v));
        ++drawn_rows;
      }
    return drawn;
  };
  const std::string whole = olt::encode_jpeg_in_strips(now), before_jpg = olt::encode_jpeg_in_strips(before);
  const std::vector<bool> rows = olt::whole_strips(rows_of(before, now), olt::jpeg_strip_rows(3));
  CHECK(olt::redrawn_jpeg_strips(&before_jpg, rows, draw) == whole);
  CHECK(drawn_rows == olt::jpeg_strip_rows(3));  // one strip
  // Bytes that are not its strips (encoded whole, or cut short), or none: drawn whole, not in part.
  const std::string plain = olt::encode_jpeg(before), cut = before_jpg.substr(0, before_jpg.size() / 2);
  for (const std::string* bytes : {&plain, &cut, static_cast<const std::string*>(nullptr)})
    CHECK(olt::redrawn_jpeg_strips(bytes, bytes ? rows : std::vector<bool>(), draw) == whole);
  // No rows said: drawn whole, once.
  drawn_rows = 0;
  CHECK(olt::redrawn_jpeg_strips(&before_jpg, {}, draw) == whole);
  CHECK(drawn_rows == now.rows);
}

TEST_CASE("whole strips: every row of a strip flagged where one is, the last strip short") {
  const std::vector<bool> rows = {false, false, false, true, false, false, false, false, true, false};
  CHECK(olt::whole_strips(rows, 4) ==
        std::vector<bool>{true, true, true, true, false, false, false, false, true, true});
  CHECK(olt::whole_strips(rows, 1) == rows);
  CHECK(olt::whole_strips({}, 16).empty());
  CHECK_THROWS_AS(olt::whole_strips(rows, 0), std::invalid_argument);
}

TEST_CASE("the rows that differ between two images, compared only where asked") {
  const cv::Mat before = labels(64, 40, 3);
  cv::Mat now = before.clone();
  now.at<uint16_t>(5, 39) ^= 1;  // the last pixel of row 5
  now.at<uint16_t>(40, 0) ^= 1;  // the first of row 40
  std::vector<bool> expected(64, false);
  expected[5] = expected[40] = true;
  CHECK(olt::differing_rows(now, before) == expected);
  std::vector<bool> maybe(64, false);  // row 40 not asked about: reported the same
  maybe[5] = maybe[6] = true;
  expected[40] = false;
  CHECK(olt::differing_rows(now, before, maybe) == expected);
  expected[40] = true;  // flags of another length: every row compared
  CHECK(olt::differing_rows(now, before, std::vector<bool>(3, false)) == expected);
  // Images of another size or type: every row.
  CHECK(olt::differing_rows(now, before.rowRange(0, 63)) == std::vector<bool>(64, true));
  cv::Mat wider;
  now.convertTo(wider, CV_32S);
  CHECK(olt::differing_rows(wider, before) == std::vector<bool>(64, true));
}
