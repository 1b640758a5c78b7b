#pragma once
// MRPT rawlogs (the original toolkit's format): 2D laser scans, odometry (the action/sensory-frame
// form and the observation-only form) and RGB-D observations, read through libmrpt, an optional
// build dependency: the `olt` binary loads libolt_rawlog.so on first use (src/modules/lazy.cpp).
// Without it, rawlog_supported() is false and read_rawlog refuses with kRawlogNeedsMrpt.
#include <functional>
#include <opencv2/core.hpp>
#include <string>

#include "olt/core/camera.h"
#include "olt/model/laser.h"

namespace olt {

/// One CObservation3DRangeScan, in OLT's conventions: poses of optical frames (x right, y down,
/// z forward), depth along the optical axis.
struct RawlogRgbd {
  std::string sensor;         ///< the observation's sensorLabel
  double timestamp = 0;       ///< UNIX seconds
  cv::Mat depth;              ///< CV_16UC1, depth * depth_scale, 0 = none
  double depth_scale = 1000;  ///< units per metre (1 / rangeUnits)
  cv::Mat color;              ///< CV_8UC3 BGR, empty when the observation has no intensity image
  Intrinsics depth_intrinsics, color_intrinsics;
  Pose T_robot_sensor = Pose::Identity();  ///< the depth camera on the robot
  Pose T_color_depth = Pose::Identity();   ///< depth camera frame -> colour camera frame
};

struct RawlogVisitor {
  std::function<void(LaserScan&&, const std::string& sensor)> scan;
  std::function<void(const OdometrySample&)> odometry;  ///< the robot's odometry pose, integrated from the start
  std::function<void(RawlogRgbd&&)> rgbd;
};

/// What read_rawlog says where OLT was built without libmrpt.
inline constexpr const char* kRawlogNeedsMrpt =
    "reading MRPT rawlogs needs OLT's rawlog module (libolt_rawlog.so), built where libmrpt-obs-dev is "
    "installed (docker/install-deps.sh); the container image olt:full has it";

bool rawlog_supported();

/// Reads `file` in order, calling the visitor per entry (external images from the folder MRPT
/// expects next to it). Throws InputError naming the file on anything unreadable.
void read_rawlog(const std::string& file, const RawlogVisitor& visit);

}  // namespace olt
