// What splicing an overlay JPEG costs against encoding only the rows it encodes again: a 640x480
// colour picture, rows 96.. of it changed (whole strips) (16 to 480 rows), splice_jpeg_strips of its strips before
// against encode_jpeg_in_strips of those rows alone (the least a splice can cost), in this process,
// in turn; medians of 15 timings of 50 each. The splice's extra is finding the strips in the JPEG
// before and joining them.
//   olt_bench_strips

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "olt/core/image.h"
#include "olt/core/image_strips.h"

using namespace olt;

namespace {

// Seconds a call of `work`: the median of 15 timings of 50 calls.
template <class Work>
double median_seconds(const Work& work) {
  std::vector<double> each;
  for (int timing = 0; timing < 15; ++timing) {
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < 50; ++k) work();
    each.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 50);
  }
  std::nth_element(each.begin(), each.begin() + 7, each.end());
  return each[7];
}

}  // namespace

int main() {
  cv::Mat picture(480, 640, CV_8UC3);
  cv::randu(picture, 0, 60);
  cv::GaussianBlur(picture, picture, {0, 0}, 3);
  for (int i = 0; i < 40; ++i)
    cv::rectangle(picture, {i * 15, i * 10, 80, 60}, cv::Scalar(i * 6, 200 - i * 4, 100), cv::FILLED);
  const std::string before = encode_jpeg_in_strips(picture);
  std::printf("overlay JPEG 640x480 spliced in strips of %d rows, medians (ms)\n", jpeg_strip_rows(3));
  std::printf("%14s %8s %16s %7s\n", "rows changed", "splice", "those rows alone", "ratio");
  for (const int changed : {16, 48, 96, 160, 480}) {
    const int first = changed == 480 ? 0 : 96, last = std::min(480, first + changed);  // whole strips
    std::vector<bool> rows(480, false);
    std::fill(rows.begin() + first, rows.begin() + last, true);
    size_t bytes = 0;
    if (!splice_jpeg_strips(before, picture, rows)) return 1;  // not its strips: nothing to time
    const double splice = median_seconds([&] { bytes += splice_jpeg_strips(before, picture, rows)->size(); });
    const double alone = median_seconds([&] { bytes += encode_jpeg_in_strips(picture.rowRange(first, last)).size(); });
    std::printf("%14d %8.3f %16.3f %7.2f\n", changed, splice * 1e3, alone * 1e3, splice / alone);
    if (bytes == 0) return 1;  // used: the calls are not optimized away
  }
  return 0;
}
