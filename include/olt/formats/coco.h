#pragma once
// COCO instance annotations (https://cocodataset.org/#format-data): masks as run-length encodings
// in the compressed string form of the COCO API (column-major runs starting with background,
// each run stored as the difference to the run two before, in 5-bit groups with a continuation
// bit, offset by 48 into printable ASCII).
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace olt {

/// Column-major run lengths of a binary mask (CV_8U, non-zero = inside), starting with a
/// (possibly empty) background run.
std::vector<uint32_t> mask_runs(const cv::Mat& mask);

/// The mask of one value of a label image: its runs (as mask_runs gives them), area and bounding box.
struct ValueMask {
  std::vector<uint32_t> runs;
  int64_t area = 0;  ///< pixels
  cv::Rect bbox;
};

/// The masks of every value of a 16-bit label image except `skip`, in one pass (instead of one
/// full-image mask per value).
std::map<uint16_t, ValueMask> value_masks(const cv::Mat& labels, const std::vector<uint16_t>& skip);

/// The compressed COCO string of run lengths.
std::string coco_rle_string(const std::vector<uint32_t>& runs);

/// One value's COCO mask: its compressed run lengths, area and bounding box.
struct CocoMask {
  std::string counts;
  int64_t area = 0;
  cv::Rect bbox;
};

/// The COCO masks of a label image's values, as a labeled frame leaves them for the export (which
/// then need not decode the image again).
struct FrameMasks {
  cv::Size size;
  std::map<uint16_t, CocoMask> masks;
};

/// The COCO masks of every value of a 16-bit label image except `skip`.
FrameMasks frame_masks(const cv::Mat& labels, const std::vector<uint16_t>& skip);

/// frame_masks(labels, skip) made from `before`, frame_masks of `before_labels`: only the values with
/// pixels in a row that differs between the images (before or now) are found again, in the columns
/// they can reach; the others are before's. Found whole where the sizes differ.
FrameMasks frame_masks_changed(const cv::Mat& labels, const std::vector<uint16_t>& skip, const FrameMasks& before,
                               const cv::Mat& before_labels);

/// frame_masks_changed where the rows that differ are known: `changed_rows`, differing_rows(labels,
/// before_labels).
FrameMasks frame_masks_changed(const cv::Mat& labels, const std::vector<uint16_t>& skip, const FrameMasks& before,
                               const cv::Mat& before_labels, const std::vector<bool>& changed_rows);

/// Masks as JSON text: {"height", "width", "masks": [{"value", "counts", "area", "bbox": [x, y, w, h]}]}.
std::string frame_masks_text(const FrameMasks& frame);

/// frame_masks_text of frame_masks(labels, skip).
std::string frame_masks_text(const cv::Mat& labels, const std::vector<uint16_t>& skip);

/// Reads frame_masks_text's text; throws InputError naming `file` where it is not that.
FrameMasks read_frame_masks(const std::string& text, const std::string& file);

/// The bytes `frame`'s masks take besides the FrameMasks itself: their map's nodes and counts.
size_t bytes_of(const FrameMasks& frame);

}  // namespace olt
