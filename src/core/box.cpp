#include "olt/core/box.h"

namespace olt {

std::array<Eigen::Vector3d, 8> box_corners(const Box& box) {
  std::array<Eigen::Vector3d, 8> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d sign((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    corners[i] = box.T_world_box * (0.5 * sign.cwiseProduct(box.size));
  }
  return corners;
}

bool contains(const Box& box, const Eigen::Vector3d& p_world) {
  return inside_box_frame(box.T_world_box.inverse() * p_world, 0.5 * box.size);
}

Box labeling_box(const Box& box) {
  if (box.margin_m <= 0) return box;
  Box out = box;
  out.size.z() = box.size.z() - box.margin_m;
  out.T_world_box.translation() += box.T_world_box.linear().col(2) * (box.margin_m / 2);
  out.margin_m = 0;
  return out;
}

}  // namespace olt
