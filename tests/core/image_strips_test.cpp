// Images coded in strips (label PNGs in bands, overlay JPEGs with a restart marker per row of MCUs):
// any reader reads them, and an image spliced from its previous bytes where rows changed is byte for
// byte the image encoded whole.
#include "olt/core/image_strips.h"

#include <zlib.h>

#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

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

TEST_CASE("rows of an image: the rows flagged as they are, in an image of its size and type") {
  const cv::Mat image = labels(40, 7, 8);
  std::vector<bool> rows(40, false);
  rows[0] = rows[17] = rows[39] = true;
  const cv::Mat kept = olt::rows_of(image, rows);
  CHECK(kept.size() == image.size());
  CHECK(kept.type() == image.type());
  for (int v : {0, 17, 39}) CHECK(cv::countNonZero(kept.row(v) != image.row(v)) == 0);
  CHECK_THROWS_AS(olt::rows_of(image, std::vector<bool>(39, true)), std::invalid_argument);
}

TEST_CASE("a label PNG's band sums are the adler-32 of its bands' filtered bytes, joined the zlib stream's") {
  // 100 rows of 3 columns: bands of 32, 32, 32 and 4 rows; a row filtered is 1 + 2 * 3 bytes.
  const cv::Mat image = labels(100, 3, 4);
  const olt::LabelPng png = olt::label_png(image);
  REQUIRE(png.band_sums.size() == 4);
  CHECK(png.bytes == olt::encode_label_png(image));
  // Each band's filtered bytes made here by the filter's definition (the byte above subtracted).
  std::string stream;
  for (int v = 0; v < image.rows; ++v) {
    stream += '\x02';
    for (int u = 0; u < image.cols; ++u) {
      const uint16_t now = image.at<uint16_t>(v, u), above = v > 0 ? image.at<uint16_t>(v - 1, u) : 0;
      stream += static_cast<char>((now >> 8) - (above >> 8));
      stream += static_cast<char>((now & 0xFF) - (above & 0xFF));
    }
  }
  const auto adler = [](std::string_view s) {
    return static_cast<uint32_t>(
        adler32(adler32(0, nullptr, 0), reinterpret_cast<const Bytef*>(s.data()), static_cast<uInt>(s.size())));
  };
  for (size_t band = 0; band < 4; ++band)
    CHECK(png.band_sums[band] == adler(std::string_view(stream).substr(band * 32 * 7, band < 3 ? 32 * 7 : 4 * 7)));
  // The stream's checksum, the PNG's last IDAT's last 4 bytes (before its CRC and IEND's 12 bytes).
  const std::string tail = png.bytes.substr(png.bytes.size() - 12 - 4 - 4, 4);
  const auto* t = reinterpret_cast<const unsigned char*>(tail.data());
  CHECK(((uint32_t{t[0]} << 24) | (uint32_t{t[1]} << 16) | (uint32_t{t[2]} << 8) | t[3]) == adler(stream));
}

TEST_CASE("a label PNG spliced where rows changed is the PNG encoded whole") {
  const cv::Mat before = labels(480, 640, 11);
  const olt::LabelPng before_png = olt::label_png(before);
  const auto splice = [&](const cv::Mat& now, const std::vector<bool>& changed) {
    return olt::splice_label_png(before_png.bytes, before_png.band_sums, now, changed);
  };
  const auto spliced_is_whole = [&](const cv::Mat& now) {
    const olt::LabelPng spliced = splice(now, olt::differing_rows(now, before));
    const olt::LabelPng whole = olt::label_png(now);
    CHECK(spliced.bytes == whole.bytes);
    CHECK(spliced.band_sums == whole.band_sums);
    CHECK(same_pixels(olt::decode_grey16(spliced.bytes, "now.png"), now));
    // Told that every row differs, or told nothing usable (flags of another length): the same bytes.
    CHECK(splice(now, std::vector<bool>(static_cast<size_t>(now.rows), true)).bytes == whole.bytes);
    CHECK(splice(now, std::vector<bool>(3, false)).bytes == whole.bytes);
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
  SECTION("an image whose last band is short: a row of it, the row above it, the last row") {
    const cv::Mat short_before = labels(100, 3, 21);  // bands of rows 0-31, 32-63, 64-95, 96-99
    const olt::LabelPng short_png = olt::label_png(short_before);
    for (int v : {95, 96, 99}) {
      cv::Mat now = short_before.clone();
      now.at<uint16_t>(v, 1) ^= 0x0101;
      const olt::LabelPng spliced =
          olt::splice_label_png(short_png.bytes, short_png.band_sums, now, olt::differing_rows(now, short_before));
      CHECK(spliced.bytes == olt::encode_label_png(now));
      CHECK(spliced.band_sums == olt::label_png(now).band_sums);
    }
  }
  SECTION("nothing: the same bytes") { CHECK(splice(before, std::vector<bool>(480, false)).bytes == before_png.bytes); }
  SECTION("bytes or sums that are not such a PNG's, or labels of another size: encoded whole") {
    const cv::Mat now = labels(480, 640, 13);
    const std::string whole = olt::encode_label_png(now);
    const std::vector<bool> none(480, false);
    const auto& sums = before_png.band_sums;
    CHECK(olt::splice_label_png("", sums, now, none).bytes == whole);
    CHECK(olt::splice_label_png(before_png.bytes.substr(0, before_png.bytes.size() - 20), sums, now, none).bytes ==
          whole);
    CHECK(olt::splice_label_png(olt::encode_png(before), sums, now, none).bytes == whole);
    const olt::LabelPng shorter = olt::label_png(before.rowRange(0, 479));
    CHECK(olt::splice_label_png(shorter.bytes, shorter.band_sums, now, none).bytes == whole);
    // The sums of another image, or too few: not this PNG's.
    CHECK(olt::splice_label_png(before_png.bytes, olt::label_png(now).band_sums, now, none).bytes == whole);
    CHECK(
        olt::splice_label_png(before_png.bytes, std::vector<uint32_t>(sums.begin(), sums.end() - 1), now, none).bytes ==
        whole);
  }
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

TEST_CASE("a JPEG spliced where any set of strips changed, apart or in runs, is it encoded whole") {
  std::mt19937 random(11);
  int apart = 0, with_short_last = 0;  // trials whose changed strips are two runs or more; hold a short last
  for (const cv::Mat& before :
       {photo(480, 640, 3), photo(53, 70, 3), photo(37, 29, 1), photo(11, 40, 3), photo(5, 20, 1)}) {
    const int strip = olt::jpeg_strip_rows(before.channels()), strips = (before.rows + strip - 1) / strip;
    const std::string before_jpg = olt::encode_jpeg_in_strips(before);
    for (int trial = 0; trial < 12; ++trial) {
      cv::Mat now = before.clone();
      for (int k = 0; k < strips; ++k)  // each strip changed or not, the first, last and short ones too
        if (random() % 3 == 0) now.row(std::min(before.rows - 1, k * strip + static_cast<int>(random() % strip))) += 40;
      const std::vector<bool> rows = rows_of(before, now);
      std::vector<bool> changed(static_cast<size_t>(strips), false);
      for (int v = 0; v < before.rows; ++v)
        if (rows[v]) changed[v / strip] = true;
      int runs = 0;
      for (int k = 0; k < strips; ++k) runs += changed[k] && (k == 0 || !changed[k - 1]);
      apart += runs >= 2;
      with_short_last += before.rows % strip != 0 && changed.back();
      INFO(before.cols << "x" << before.rows << ", trial " << trial);
      CHECK(olt::splice_jpeg_strips(before_jpg, now, rows) == olt::encode_jpeg_in_strips(now));
    }
  }
  CHECK(apart >= 10);
  CHECK(with_short_last >= 5);
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
