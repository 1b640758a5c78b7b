#pragma once
// A keyframe of RegistrationOdometry's memory `keyframes` (private to src/poses).
#include <memory>
#include <optional>

#include "olt/poses/registration_poses.h"

namespace olt {

// A registered frame: a keyframe (a graph node) or the last frame of a sensor (the next one's target).
struct RegistrationOdometry::Keyframe {
  std::string sensor;
  double timestamp = 0;
  PointSet cloud;  ///< the sensor frame
  std::unique_ptr<KdTree> tree;
  std::optional<IntensityImage> image;     ///< colour term target
  Pose T_color_sensor = Pose::Identity();  ///< the colour camera at its capture time, from the sensor's frame
  PhotometricPoints color_points;          ///< its own textured points (sensor frame), as a loop source
};

/// A sensor's chain of frame-to-frame registrations since its last keyframe.
struct RegistrationOdometry::SensorTrack {
  std::shared_ptr<Keyframe> frame;  ///< the last registered frame: the next one's target
  size_t keyframe = 0;              ///< where the chain started
  Pose T_keyframe_frame = Pose::Identity();
  int links = 0;     ///< registrations since the keyframe
  int failures = 0;  ///< failed registrations since the last good one
};

}  // namespace olt
