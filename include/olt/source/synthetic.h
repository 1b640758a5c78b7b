#pragma once
// A built-in recording with exact ground truth: a room with furniture-sized blocks, rendered by ray
// casting, so every pixel's depth, colour and object is exact and label propagation can be checked
// against the truth. Two ways to see it:
//  - hand-held (cameras = 0): one RGB-D camera moving along a smooth arc around the table;
//  - a robot (cameras = 1..4): a robot driving a loop around the table with a 2D laser (HOKUYO1)
//    and RGB-D cameras RGBD_1..n on the Robot@Home rig, wheel odometry that drifts, laser range
//    noise and depth noise growing with range; deterministic for a seed.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/camera.h"
#include "olt/model/laser.h"
#include "olt/model/trajectory.h"

namespace olt {

struct SyntheticConfig {
  int frames = 30;            ///< RGB-D observations (per camera for a robot)
  int width = 640;            ///< image width, pixels
  int height = 480;           ///< image height, pixels
  double rate_hz = 10;        ///< observations per second (per camera)
  double depth_scale = 5000;  ///< depth PNG units per metre (TUM's convention)
  int cameras = 0;            ///< 0: hand-held camera; 1..4: a robot with this many cameras and a laser
  unsigned seed = 1;          ///< robot: the noise and odometry drift
  /// Observation k's colour image is taken (and stamped) this long after its depth image, with
  /// alternating sign (+, -, +, ...), seconds: the two captures of a Kinect-class camera apart.
  double color_dt_s = 0;
  /// The frame the truth is given in (poses, boxes) tilted this far from gravity, degrees, as a
  /// motion-capture or first-camera frame is: see synthetic_truth_frame.
  double tilt_deg = 0;
};

struct SyntheticScene {
  SyntheticConfig config;
  Intrinsics camera;                 ///< every camera's; depth and colour share it (registered, no distortion)
  std::vector<Box> objects;          ///< the solid blocks, exact
  std::vector<Box> annotations;      ///< one box per object, as an annotator would draw it
  std::vector<std::string> sensors;  ///< camera ids
  std::vector<Pose> T_robot_camera;  ///< per camera (identity when hand-held)
  // Per observation, in time order:
  std::vector<double> timestamps;
  std::vector<int> camera_of;        ///< index into sensors
  std::vector<Pose> T_world_camera;  ///< exact pose
  std::vector<double> color_dt_s;    ///< the colour image's time minus the depth image's
  std::vector<Pose> T_world_color;   ///< exact pose of the camera when the colour image was taken
  // A robot only:
  Trajectory robot_truth;                ///< exact T_world_robot, 100 Hz
  std::vector<LaserScan> scans;          ///< 10 Hz, 240 degrees, 0.5 degree steps, range noise 1 cm
  std::vector<OdometrySample> odometry;  ///< integrated with scale, heading and random errors
};

struct SyntheticFrame {
  cv::Mat depth;   ///< CV_16UC1, metres * depth_scale, 0 = no return
  cv::Mat color;   ///< CV_8UC3, BGR, seen from T_world_color
  cv::Mat object;  ///< CV_16UC1, 0 = room (walls, floor, ceiling), i + 1 = objects[i]
};

SyntheticScene make_synthetic_scene(const SyntheticConfig& config);

/// T_truth_room: the room's gravity-aligned frame (z up, floor at z = 0) in the frame the recording's
/// truth is given in: tilted by `tilt_deg` about the horizontal axis (cos 30°, sin 30°, 0) and
/// shifted by (0.4, -0.3, 0.2) m where tilt_deg is not 0; identity otherwise.
Pose synthetic_truth_frame(double tilt_deg);
/// The exact images of observation `index`, depth noise added for a robot (the object image stays
/// exact: which surface each pixel's ray hits).
SyntheticFrame render_synthetic_frame(const SyntheticScene& scene, size_t index);

}  // namespace olt
