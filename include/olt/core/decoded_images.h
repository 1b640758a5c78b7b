#pragma once
// Decoded images kept between the runs of one process: `olt watch` relabels the frames that see the
// edited box edit after edit, and decoding their depth and colour PNGs is about half of that work.
#include <cstddef>
#include <opencv2/core.hpp>

#include "olt/core/fs.h"

namespace olt {

/// From now on, keep up to `budget_bytes` of decoded images (0, the default: keep none), the least
/// recently read dropped first. An image is found again by its path and its file's size,
/// modification time and inode, so a file replaced or edited is decoded afresh.
void keep_decoded_images(size_t budget_bytes);

/// read_grey16 and read_color through the images kept. The images returned may be shared with the
/// keeper and later readers: read them, never write into them. Thread-safe.
cv::Mat remembered_grey16(const fs::path& file);
cv::Mat remembered_color(const fs::path& file);

}  // namespace olt
