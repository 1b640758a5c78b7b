#pragma once
// Voxel fusion of back-projected RGB-D observations into one coloured cloud. Memory is bounded by
// the scene (one accumulator per occupied voxel), not by the number of frames, which is why this
// streams frames into a hash map instead of collecting every point for pcl::VoxelGrid.
#include <opencv2/core.hpp>
#include <unordered_map>
#include <vector>

#include "olt/model/cloud.h"
#include "olt/model/recording.h"

namespace olt {

class VoxelFusion {
 public:
  explicit VoxelFusion(double voxel_size_m);
  void add(const Eigen::Vector3d& p_world, const cv::Vec3b& bgr);
  /// One point per voxel: the mean position and mean colour, sorted by voxel (deterministic).
  ColoredCloud cloud() const;
  size_t voxels() const { return voxels_.size(); }

 private:
  struct Accumulator {
    double x = 0, y = 0, z = 0;
    uint64_t r = 0, g = 0, b = 0, n = 0;
  };
  double voxel_size_m_;
  std::unordered_map<uint64_t, Accumulator> voxels_;
};

/// Adds every `stride`-th pixel (in both directions) of one observation. Colour comes from projecting
/// the depth point into the colour camera; without a colour image points are grey by depth.
void fuse_observation(VoxelFusion& fusion, const cv::Mat& depth, const cv::Mat& color_bgr,
                      const SensorCalibration& calibration, const std::vector<Eigen::Vector2f>& rays,
                      const Pose& T_world_sensor, int stride);

}  // namespace olt
