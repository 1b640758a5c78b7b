#pragma once
// A built-in recording with exact ground truth: a room with furniture-sized blocks, seen by one
// RGB-D camera moving along a smooth arc, rendered by ray casting. Every pixel's depth, colour and
// object is exact, so label propagation can be checked against the truth.
#include <opencv2/core.hpp>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/camera.h"

namespace olt {

struct SyntheticConfig {
  int frames = 30;            ///< number of RGB-D observations
  int width = 640;            ///< image width, pixels
  int height = 480;           ///< image height, pixels
  double rate_hz = 10;        ///< observations per second
  double depth_scale = 5000;  ///< depth PNG units per metre (TUM's convention)
};

struct SyntheticScene {
  SyntheticConfig config;
  Intrinsics camera;             ///< depth and colour share it (registered, no distortion)
  std::vector<Box> objects;      ///< the solid blocks, exact
  std::vector<Box> annotations;  ///< one box per object, as an annotator would draw it
  std::vector<double> timestamps;
  std::vector<Pose> T_world_camera;  ///< exact pose of each observation
};

struct SyntheticFrame {
  cv::Mat depth;   ///< CV_16UC1, metres * depth_scale, 0 = no return
  cv::Mat color;   ///< CV_8UC3, BGR
  cv::Mat object;  ///< CV_16UC1, 0 = room (walls, floor, ceiling), i + 1 = objects[i]
};

SyntheticScene make_synthetic_scene(const SyntheticConfig& config);
SyntheticFrame render_synthetic_frame(const SyntheticScene& scene, size_t index);

}  // namespace olt
