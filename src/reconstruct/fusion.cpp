#include "olt/reconstruct/fusion.h"

#include <algorithm>
#include <cmath>

#include "olt/core/voxel.h"

namespace olt {

VoxelFusion::VoxelFusion(double voxel_size_m) : voxel_size_m_(voxel_size_m) {}

void VoxelFusion::add(const Eigen::Vector3d& p, const cv::Vec3b& bgr) {
  Accumulator& a = voxels_[voxel_key(p, voxel_size_m_)];
  a.x += p.x();
  a.y += p.y();
  a.z += p.z();
  a.b += bgr[0];
  a.g += bgr[1];
  a.r += bgr[2];
  ++a.n;
}

ColoredCloud VoxelFusion::cloud() const {
  std::vector<std::pair<uint64_t, const Accumulator*>> sorted;
  sorted.reserve(voxels_.size());
  for (const auto& [key, a] : voxels_) sorted.emplace_back(key, &a);
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  ColoredCloud out;
  out.reserve(sorted.size());
  for (const auto& [key, a] : sorted) {
    const double n = static_cast<double>(a->n);
    out.push_back({static_cast<float>(a->x / n), static_cast<float>(a->y / n), static_cast<float>(a->z / n),
                   static_cast<uint8_t>((a->r + a->n / 2) / a->n), static_cast<uint8_t>((a->g + a->n / 2) / a->n),
                   static_cast<uint8_t>((a->b + a->n / 2) / a->n)});
  }
  return out;
}

void fuse_observation(VoxelFusion& fusion, const cv::Mat& depth, const cv::Mat& color_bgr, const SensorCalibration& cal,
                      const std::vector<Eigen::Vector2f>& rays, const Pose& T_world_sensor, int stride) {
  for (int v = 0; v < depth.rows; v += stride) {
    for (int u = 0; u < depth.cols; u += stride) {
      const double z = depth.at<uint16_t>(v, u) / cal.depth_scale;
      if (z <= 0 || z < cal.min_depth_m || z > cal.max_depth_m) continue;
      const Eigen::Vector2f& ray = rays[static_cast<size_t>(v) * depth.cols + u];
      const Eigen::Vector3d p(ray.x() * z, ray.y() * z, z);
      cv::Vec3b bgr;
      Eigen::Vector2d px;
      if (color_bgr.empty()) {
        const auto grey = static_cast<uchar>(std::clamp(255.0 * (1.0 - z / cal.max_depth_m), 0.0, 255.0));
        bgr = cv::Vec3b(grey, grey, grey);
      } else if (project(cal.color, cal.T_color_depth * p, &px)) {
        const int cu = static_cast<int>(std::lround(px.x())), cv_row = static_cast<int>(std::lround(px.y()));
        if (cu < 0 || cv_row < 0 || cu >= color_bgr.cols || cv_row >= color_bgr.rows) continue;
        bgr = color_bgr.at<cv::Vec3b>(cv_row, cu);
      } else {
        continue;
      }
      fusion.add(T_world_sensor * p, bgr);
    }
  }
}

}  // namespace olt
