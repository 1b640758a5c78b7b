#pragma once
// The `calibrate` stage: per-sensor intrinsics, depth scale and range, extrinsics. Each sensor starts
// from what the recording knows (synthetic, rawlog), then a named preset, then the numbers in the job.
#include <map>
#include <string>
#include <vector>

#include "olt/model/recording.h"

namespace olt {

struct SensorConfig {
  std::string preset = "none";           ///< none | tum_fr1 | tum_fr2 | tum_fr3 | tum_ros_default
  std::vector<double> depth_intrinsics;  ///< fx fy cx cy, pixels
  std::vector<double> depth_distortion;  ///< k1 k2 p1 p2 k3
  std::vector<double> color_intrinsics;  ///< fx fy cx cy, pixels (default: the depth camera's)
  std::vector<double> color_distortion;  ///< k1 k2 p1 p2 k3 (default: the depth camera's)
  double depth_scale = 0;                ///< depth units per metre; 0 = from the preset or recording
  double min_depth_m = 0.1;              ///< nearer readings are ignored, metres
  double max_depth_m = 10;               ///< farther readings are ignored, metres
  double time_offset_s = 0;              ///< added to the depth timestamps to get the pose source's time, seconds
  std::vector<double> pose_on_robot;     ///< x y z (m) yaw pitch roll (deg); default identity
  std::vector<double> color_from_depth;  ///< T_color_depth as x y z (m) yaw pitch roll (deg); default identity
};

struct CalibrateConfig {
  std::map<std::string, SensorConfig> sensors;  ///< by sensor id
};

struct CalibrateInputs {
  std::string stage;                ///< the stage's id, for messages
  std::vector<SensorInfo> sensors;  ///< the recording's
};

/// Throws InputError for a sensor without intrinsics or depth scale, or a configured sensor the
/// recording does not have.
Calibration run_calibrate(const CalibrateInputs& in, const CalibrateConfig& c);

}  // namespace olt
