#pragma once
// Voxel hashing shared by fusion and downsampling: 21 bits per axis, offset so that coordinates
// within about +-10 km of the origin at 1 cm voxels stay unique.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace olt {

inline uint64_t voxel_key(const Eigen::Vector3d& p, double voxel_size_m) {
  auto cell = [&](double v) {
    return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v / voxel_size_m)) + (1 << 20)) & 0x1FFFFF;
  };
  return (cell(p.x()) << 42) | (cell(p.y()) << 21) | cell(p.z());
}

}  // namespace olt
