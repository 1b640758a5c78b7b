#pragma once
// Decoded images kept between the runs of one process: `olt watch` relabels the frames that see the
// edited box edit after edit, and decoding their depth and colour PNGs is about half of that work;
// the labels it made are kept too, to start the next edit's labels from.
#include <cstddef>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

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

/// Images a stage made, kept under a name of its own within the same budget (none kept when it is 0):
/// `olt watch` keeps each frame's labels, so the next edit relabels only the pixels it reaches. The
/// images are shared: never write into them. Thread-safe.
void remember_images(const std::string& name, std::vector<cv::Mat> images);
/// The images kept under `name`; none when they are not (never kept, or dropped for the budget).
std::optional<std::vector<cv::Mat>> remembered_images(const std::string& name);

}  // namespace olt
