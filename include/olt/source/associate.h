#pragma once
// Pairing of depth and colour images by timestamp (the TUM benchmark's associate step).
#include <optional>
#include <vector>

namespace olt {

/// For each depth timestamp, the index of the nearest colour timestamp when it is within
/// `max_difference_s`, else nothing. Both lists must be sorted ascending.
std::vector<std::optional<size_t>> associate_nearest(const std::vector<double>& depth_times,
                                                     const std::vector<double>& color_times, double max_difference_s);

}  // namespace olt
