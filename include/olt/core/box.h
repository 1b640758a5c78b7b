#pragma once
// An oriented 3D box annotation in the scene (world) frame, and point-in-box tests.
#include <array>
#include <string>

#include "olt/core/geometry.h"

namespace olt {

struct Box {
  std::string id;                                  ///< unique within an annotation set
  std::string label;                               ///< class name, e.g. "monitor"
  std::string instance;                            ///< instance name, e.g. "monitor_1"; defaults to the box id
  Pose T_world_box = Pose::Identity();             ///< centre and orientation
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< full extents along the box's x, y, z, metres
  int priority = 0;     ///< where boxes overlap, the higher priority labels (then the smaller volume)
  double margin_m = 0;  ///< labels only above this height over the box's bottom face (the floor under it)

  double volume() const { return size.x() * size.y() * size.z(); }
};

/// The eight corners in the world frame; corner i has local signs (x: bit 0, y: bit 1, z: bit 2),
/// a set bit meaning +size/2.
std::array<Eigen::Vector3d, 8> box_corners(const Box& box);

/// The part of the box that labels: its bottom face raised by margin_m (the box unchanged when 0).
Box labeling_box(const Box& box);

/// True when `p_box` (a point already in the box frame) lies inside or on the box.
inline bool inside_box_frame(const Eigen::Vector3d& p_box, const Eigen::Vector3d& half_size) {
  return std::abs(p_box.x()) <= half_size.x() && std::abs(p_box.y()) <= half_size.y() &&
         std::abs(p_box.z()) <= half_size.z();
}

bool contains(const Box& box, const Eigen::Vector3d& p_world);

}  // namespace olt
