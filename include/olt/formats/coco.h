#pragma once
// COCO instance annotations (https://cocodataset.org/#format-data): masks as run-length encodings
// in the compressed string form of the COCO API (column-major runs starting with background,
// each run stored as the difference to the run two before, in 5-bit groups with a continuation
// bit, offset by 48 into printable ASCII).
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace olt {

/// Column-major run lengths of a binary mask (CV_8U, non-zero = inside), starting with a
/// (possibly empty) background run.
std::vector<uint32_t> mask_runs(const cv::Mat& mask);

/// The compressed COCO string of run lengths.
std::string coco_rle_string(const std::vector<uint32_t>& runs);

}  // namespace olt
