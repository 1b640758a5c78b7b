#pragma once
// The parts of the synthetic recording shared by its files: synthetic.cpp (the room, its objects,
// rendering, the hand-held camera) and synthetic_robot.cpp (the robot: rig, path, laser, odometry).
#include <random>
#include <vector>

#include "olt/source/synthetic.h"

namespace olt {

/// The clock of the first observation (hand-held) and of the robot's start, seconds.
constexpr double kStartTime = 1000.0;

/// The nearest surface along a ray: the distance, its normal, the object (-1: the room) and the room
/// surface.
struct Hit {
  double t = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  int object = -1;
  int surface = 0;
};

/// The room and its objects, ready for rays: each object's inverse pose is computed once, not once
/// per ray (a frame casts 77k-307k rays at 10-12 objects).
class RayTracer {
 public:
  explicit RayTracer(const std::vector<Box>& objects);
  /// The nearest of the room and the objects along the ray from `origin` in direction `d` (unit).
  Hit cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& d) const;

 private:
  const std::vector<Box>& objects_;
  std::vector<Pose> box_from_world_;
};

/// The robot's cameras, observations, exact path, laser scans and drifting odometry, into `scene`
/// (whose objects are already placed).
void make_robot(SyntheticScene& scene, std::mt19937& rng);

}  // namespace olt
