#include "olt/source/associate.h"

#include <algorithm>
#include <cmath>

namespace olt {

std::vector<std::optional<size_t>> associate_nearest(const std::vector<double>& depth_times,
                                                     const std::vector<double>& color_times, double max_difference_s) {
  std::vector<std::optional<size_t>> pairs;
  pairs.reserve(depth_times.size());
  for (double t : depth_times) {
    const auto after = std::lower_bound(color_times.begin(), color_times.end(), t);
    std::optional<size_t> best;
    double best_dt = max_difference_s;
    for (auto it : {after - (after != color_times.begin() ? 1 : 0), after}) {
      if (it == color_times.end()) continue;
      const double dt = std::abs(*it - t);
      if (dt <= best_dt) {
        best_dt = dt;
        best = static_cast<size_t>(it - color_times.begin());
      }
    }
    pairs.push_back(best);
  }
  return pairs;
}

}  // namespace olt
