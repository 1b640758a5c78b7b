#include "olt/formats/coco.h"

namespace olt {

std::vector<uint32_t> mask_runs(const cv::Mat& mask) {
  std::vector<uint32_t> runs;
  bool inside = false;
  uint32_t count = 0;
  for (int u = 0; u < mask.cols; ++u) {
    for (int v = 0; v < mask.rows; ++v) {
      const bool here = mask.at<uint8_t>(v, u) != 0;
      if (here != inside) {
        runs.push_back(count);
        count = 0;
        inside = here;
      }
      ++count;
    }
  }
  runs.push_back(count);
  return runs;
}

std::string coco_rle_string(const std::vector<uint32_t>& runs) {
  std::string text;
  for (size_t i = 0; i < runs.size(); ++i) {
    int64_t x = runs[i];
    if (i > 2) x -= static_cast<int64_t>(runs[i - 2]);
    bool more = true;
    while (more) {
      int64_t c = x & 0x1f;
      x >>= 5;  // arithmetic shift: negative differences end in all ones
      more = (c & 0x10) ? x != -1 : x != 0;
      if (more) c |= 0x20;
      text.push_back(static_cast<char>(c + 48));
    }
  }
  return text;
}

}  // namespace olt
