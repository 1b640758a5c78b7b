// COCO compressed RLE against hand-computed strings, and decoding back to the same mask.
#include "olt/formats/coco.h"

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "support/temp_dir.h"

using namespace olt;
using olt::test::decode_coco_rle;

TEST_CASE("COCO RLE strings computed by hand") {
  // 2x2 mask, column-major 0 1 1 0: runs 1, 2, 1
  cv::Mat mask = (cv::Mat_<uint8_t>(2, 2) << 0, 1, 1, 0);
  CHECK(mask_runs(mask) == std::vector<uint32_t>{1, 2, 1});
  CHECK(coco_rle_string({1, 2, 1}) == "121");
  // the 4th run is stored as 7 - 3 = 4
  CHECK(coco_rle_string({5, 3, 2, 7}) == "5324");
  // a negative difference, 1 - 10 = -9: low 5 bits 10111 = 23 -> 'G', sign bit set, no continuation
  CHECK(coco_rle_string({0, 10, 2, 1}) == "0:2G");
  // 40 needs two groups: 8 | 0x20 -> 'X', then 1 -> '1'
  CHECK(coco_rle_string({40}) == "X1");
}

TEST_CASE("COCO RLE decodes back to the runs of random masks") {
  cv::Mat mask(37, 53, CV_8U);
  cv::RNG rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    rng.fill(mask, cv::RNG::UNIFORM, 0, 2);
    if (trial % 2) mask(cv::Rect(0, 0, 53, 10)).setTo(1);  // long runs too
    const auto runs = mask_runs(mask);
    CHECK(decode_coco_rle(coco_rle_string(runs)) == runs);
    uint32_t total = 0;
    for (auto r : runs) total += r;
    CHECK(total == 37u * 53u);
  }
}

TEST_CASE("value_masks gives, for every value, the runs, area and box of its own mask in one pass") {
  cv::Mat labels(7, 5, CV_16UC1, cv::Scalar(0));
  cv::RNG rng(7);
  for (int v = 0; v < labels.rows; ++v)
    for (int u = 0; u < labels.cols; ++u) labels.at<uint16_t>(v, u) = static_cast<uint16_t>(rng.uniform(0, 4));
  labels.at<uint16_t>(6, 4) = 9;  // a value only in the last pixel: no trailing background run
  const auto masks = value_masks(labels, {0});
  CHECK(masks.count(0) == 0);
  for (uint16_t value : {1, 2, 3, 9}) {
    INFO("value " << value);
    const cv::Mat mask = labels == value;
    REQUIRE(masks.count(value) == 1);
    CHECK(masks.at(value).runs == mask_runs(mask));
    CHECK(masks.at(value).area == cv::countNonZero(mask));
    CHECK(masks.at(value).bbox == cv::boundingRect(mask));
  }
}

TEST_CASE("a frame's masks file holds every value's COCO string, area and box - bad text names the file") {
  cv::Mat labels(6, 4, CV_16UC1, cv::Scalar(0));
  labels(cv::Rect(1, 1, 2, 3)).setTo(5);
  labels.at<uint16_t>(5, 3) = 65535;
  const FrameMasks frame = read_frame_masks(frame_masks_text(labels, {0, 65535}), "masks.json");
  CHECK(frame.size == cv::Size(4, 6));
  REQUIRE(frame.masks.size() == 1);
  const CocoMask& mask = frame.masks.at(5);
  CHECK(mask.counts == coco_rle_string(mask_runs(labels == 5)));
  CHECK(mask.area == 6);
  CHECK(mask.bbox == cv::Rect(1, 1, 2, 3));
  CHECK_THROWS_WITH(read_frame_masks("{\"width\": 4}", "cache/f/masks.json"),
                    Catch::Contains("cache/f/masks.json") && Catch::Contains("not a frame's masks file"));
}

TEST_CASE("masks found again only for the values whose rows changed are the masks found whole") {
  cv::RNG rng(17);
  const auto random_labels = [&] {
    cv::Mat labels(60, 80, CV_16UC1, cv::Scalar(0));
    // A desk across the image, and a post from the top to the bottom (its runs go on from one column's
    // foot to the next one's head), under the small things.
    labels(cv::Rect(0, rng.uniform(0, 30), 80, rng.uniform(10, 30))).setTo(7);
    labels(cv::Rect(rng.uniform(0, 70), 0, rng.uniform(1, 8), 60)).setTo(8);
    for (int k = 0; k < 8; ++k)
      labels(cv::Rect(rng.uniform(0, 70), rng.uniform(0, 50), rng.uniform(1, 10), rng.uniform(1, 10)))
          .setTo(rng.uniform(1, 6));
    labels(cv::Rect(rng.uniform(0, 70), rng.uniform(0, 50), 5, 3)).setTo(65535);
    return labels;
  };
  const std::vector<uint16_t> skip = {0, 65535};
  for (int trial = 0; trial < 200; ++trial) {
    const cv::Mat before = random_labels();
    const olt::FrameMasks before_masks = olt::frame_masks(before, skip);
    cv::Mat now = before.clone();
    switch (trial % 5) {
      case 0:  // a box's pixels moved
        now(cv::Rect(rng.uniform(0, 60), rng.uniform(0, 40), 20, 20)).setTo(rng.uniform(0, 8));
        break;
      case 1:  // a value gone wherever it was, in rows far apart
        now.setTo(0, now == rng.uniform(1, 6));
        break;
      case 2:  // one pixel, in the last row
        now.at<uint16_t>(59, rng.uniform(0, 80)) = static_cast<uint16_t>(rng.uniform(0, 8));
        break;
      case 3:  // a mug moved on the desk: a few columns of values that reach all of them
        now(cv::Rect(rng.uniform(0, 74), rng.uniform(0, 56), 6, 4)).setTo(rng.uniform(0, 9));
        break;
      default:  // nothing
        break;
    }
    INFO("trial " << trial);
    CHECK(olt::frame_masks_text(olt::frame_masks_changed(now, skip, before_masks, before)) ==
          olt::frame_masks_text(now, skip));
  }
  // A desk's mask before that is not a COCO string, where a mug on it moved: found whole.
  cv::Mat before(60, 80, CV_16UC1, cv::Scalar(0));
  before.rowRange(20, 40).setTo(7);
  cv::Mat now = before.clone();
  before(cv::Rect(30, 25, 6, 4)).setTo(3);
  now(cv::Rect(40, 25, 6, 4)).setTo(3);
  // Below '0'; cut short on a continuation bit; more than seven groups; runs that are not the image's
  // 4,800 pixels (a mask of another image).
  for (const std::string& counts : std::vector<std::string>{"!?", "0P", "PPPPPPPP0", olt::coco_rle_string({5, 3})}) {
    INFO("counts " << counts);
    olt::FrameMasks garbled = olt::frame_masks(before, skip);
    garbled.masks.at(7).counts = counts;
    CHECK(olt::frame_masks_text(olt::frame_masks_changed(now, skip, garbled, before)) ==
          olt::frame_masks_text(now, skip));
  }
  // Masks of another size: found whole.
  const cv::Mat small = random_labels().rowRange(0, 30);
  const cv::Mat large = random_labels();
  CHECK(olt::frame_masks_text(olt::frame_masks_changed(large, skip, olt::frame_masks(small, skip), small)) ==
        olt::frame_masks_text(large, skip));
}
