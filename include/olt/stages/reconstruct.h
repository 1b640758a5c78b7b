#pragma once
// The `reconstruct` stage: every k-th observation with a valid pose, back-projected and voxel-fused
// into one coloured cloud, levelled into the annotation frame (olt/reconstruct/level.h) for drawing
// boxes, with a preview image and the frame's transform to the poses' frame.
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "olt/model/cloud.h"
#include "olt/model/recording.h"
#include "olt/reconstruct/level.h"

namespace olt {

struct ReconstructConfig {
  int every = 5;               ///< fuse every k-th observation
  double voxel_size_m = 0.01;  ///< edge of a fusion voxel, metres
  int pixel_stride = 2;        ///< use every n-th pixel in each direction
  int preview_size_px = 600;   ///< height of the preview image, pixels
  bool level = true;           ///< false: the scene stays in the poses' frame
  std::vector<double> up;      ///< "up" in the poses' frame, given instead of found (3 numbers)
};

struct ReconstructInputs {
  /// The recording and its poses (one per observation, in order), shared with the run's other stages.
  std::shared_ptr<const Recording> recording;
  Calibration calibration;
  std::shared_ptr<const std::vector<ObservationPose>> poses;
};

struct ReconstructResult {
  ColoredCloud cloud;  ///< annotation frame
  AnnotationFrame frame;
  cv::Mat preview;             ///< BGR
  double voxel_size_m = 0.01;  ///< the cloud's resolution (how wide the report draws a point)
  int observations_fused = 0;
};

/// Throws InputError naming a depth image whose size disagrees with its calibration.
ReconstructResult run_reconstruct(const ReconstructInputs& in, const ReconstructConfig& c);

}  // namespace olt
