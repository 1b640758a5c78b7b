// The annotation frame (olt/reconstruct/level.h): up from the horizontal planes PCL's RANSAC finds
// near the cameras' own up, then the origin and x axis from the scene.
#include "olt/reconstruct/level.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "olt/reconstruct/plane_finder.h"

namespace olt {
namespace {

constexpr size_t kMaxPoints = 20000;  // RANSAC on a sample: enough for sub-degree normals

std::vector<Eigen::Vector3f> sample(const ColoredCloud& cloud) {
  const size_t step = std::max<size_t>(1, cloud.size() / kMaxPoints);
  std::vector<Eigen::Vector3f> points;
  points.reserve(cloud.size() / step + 1);
  for (size_t i = 0; i < cloud.size(); i += step) points.emplace_back(cloud[i].x, cloud[i].y, cloud[i].z);
  return points;
}

// Up as the cameras suggest it: the camera axis that stays most nearly fixed in the world while the
// camera moves and turns. Held upright (hand-held, most rigs) that is -y of the optical frame; on a
// rig with cameras turned on their side (Robot@Home's portrait cameras) it is x, signed towards the
// poses' frame's z (a robot's frame is level by its laser). The planes then correct it by tens of
// degrees (a camera pitched down at a desk).
Eigen::Vector3d cameras_up(const std::vector<Pose>& poses) {
  Eigen::Vector3d minus_y = Eigen::Vector3d::Zero(), x = Eigen::Vector3d::Zero();
  for (const auto& T : poses) {
    minus_y -= T.linear().col(1);
    x += T.linear().col(0);
  }
  if (poses.empty() || (x.norm() < 1e-9 && minus_y.norm() < 1e-9)) return Eigen::Vector3d::UnitZ();
  if (x.z() < 0) x = -x;
  // Both fixed (a camera that barely turns): the one nearer the poses' frame's z (a motion capture's
  // or a robot's frame is about level); -y where that does not tell them apart.
  const bool x_up =
      x.norm() > 1.5 * minus_y.norm() ||
      (minus_y.norm() <= 1.5 * x.norm() && std::abs(x.normalized().z()) > std::abs(minus_y.normalized().z()) + 0.2);
  return x_up ? Eigen::Vector3d(x.normalized()) : Eigen::Vector3d(minus_y.normalized());
}

Eigen::Vector3d mean_position(const std::vector<Pose>& poses, const std::vector<Eigen::Vector3f>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  if (!poses.empty()) {
    for (const auto& T : poses) sum += T.translation();
    return sum / static_cast<double>(poses.size());
  }
  for (const auto& p : points) sum += p.cast<double>();
  return points.empty() ? sum : Eigen::Vector3d(sum / static_cast<double>(points.size()));
}

struct Up {
  Eigen::Vector3d direction;
  std::vector<Plane> planes;  ///< the horizontal planes, normals turned to `direction`
};

// The scene's largest planes, of any orientation, grouped by direction (parallel within 5 degrees,
// normals turned towards the cameras: floors and table tops are seen from above). Up is the
// direction, within `max_angle` of `prior`, whose planes hold the most points (floor and table tops
// together; walls stand perpendicular to it), their normals' mean weighted by points; none found:
// the prior, with no planes.
Up up_from_planes(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3d& prior, double max_angle,
                  const Eigen::Vector3d& viewpoint, double tolerance_m) {
  PlaneQuery query;
  query.axis = prior;
  query.max_angle_rad = M_PI / 2;  // any orientation
  query.distance_m = tolerance_m;
  query.max_planes = 6;
  query.min_inliers = std::max<size_t>(200, points.size() / 50);
  std::vector<Plane> planes;
  plane_finder().find(points, query, planes);
  for (auto& plane : planes)
    if (plane.normal.dot(viewpoint) + plane.d < 0) plane.normal = -plane.normal, plane.d = -plane.d;
  Up best{prior, {}};
  size_t best_points = 0;
  for (const auto& seed : planes) {
    Up candidate{Eigen::Vector3d::Zero(), {}};
    size_t total = 0;
    for (const auto& plane : planes)
      if (plane.normal.dot(seed.normal) > std::cos(5 * M_PI / 180)) {
        candidate.direction += static_cast<double>(plane.inliers) * plane.normal;
        candidate.planes.push_back(plane);
        total += plane.inliers;
      }
    candidate.direction.normalize();
    if (candidate.direction.dot(prior) > std::cos(max_angle) && total > best_points) {
      best = candidate;
      best_points = total;
    }
  }
  return best;
}

// Up refined over the horizontal planes together: the points within `tolerance_m` of each plane,
// each plane's centred, and the normal of least squares is the pooled scatter's weakest direction
// (the planes share it, not their heights). Twice, the second time with inliers of the first fit.
void refine_up(const std::vector<Eigen::Vector3f>& points, Up& up, double tolerance_m) {
  for (int round = 0; round < 2; ++round) {
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (auto& plane : up.planes) {
      std::vector<Eigen::Vector3d> on;
      for (const auto& p : points) {
        const Eigen::Vector3d q = p.cast<double>();
        if (std::abs(up.direction.dot(q) + plane.d) < tolerance_m) on.push_back(q);
      }
      if (on.size() < 3) continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& q : on) mean += q;
      mean /= static_cast<double>(on.size());
      for (const auto& q : on) scatter += (q - mean) * (q - mean).transpose();
      plane.d = -up.direction.dot(mean);
    }
    const Eigen::Vector3d n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(0);
    if (!n.allFinite() || n.norm() < 0.5) return;
    up.direction = n.dot(up.direction) < 0 ? Eigen::Vector3d(-n) : n;
    for (auto& plane : up.planes) plane.normal = up.direction;
  }
}

// x along the largest wall (a plane parallel to up), else along the points' main horizontal extent;
// turned to agree with the poses' frame's x where it can, so the choice is stable.
Eigen::Vector3d x_axis(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3d& up, double tolerance_m,
                       std::string* how) {
  PlaneQuery query;
  query.axis = up;
  query.perpendicular = false;
  query.max_angle_rad = 10 * M_PI / 180;
  query.distance_m = tolerance_m;
  query.max_planes = 1;
  query.min_inliers = std::max<size_t>(200, points.size() / 20);
  std::vector<Plane> walls;
  plane_finder().find(points, query, walls);
  Eigen::Vector3d x;
  if (!walls.empty()) {
    x = up.cross(walls.front().normal);
    *how = "wall";
  } else {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : points) mean += p.cast<double>();
    mean /= std::max<double>(1, static_cast<double>(points.size()));
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const auto& p : points) {
      Eigen::Vector3d q = p.cast<double>() - mean;
      q -= q.dot(up) * up;
      scatter += q * q.transpose();
    }
    x = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(2);
    *how = "extent";
  }
  x -= x.dot(up) * up;
  if (x.norm() < 1e-6) x = up.unitOrthogonal();
  x.normalize();
  // Of x and -x (and the two across), the one closest to the world's x, so small changes keep it.
  const Eigen::Vector3d y = up.cross(x);
  Eigen::Vector3d best = x;
  for (const Eigen::Vector3d& c : {x, Eigen::Vector3d(-x), y, Eigen::Vector3d(-y)})
    if (c.x() > best.x() + 1e-9) best = c;
  return best;
}

}  // namespace

double AnnotationFrame::tilt_deg() const {
  const double c = std::clamp(T_world_annotation.linear().col(2).z(), -1.0, 1.0);
  return std::acos(c) * 180 / M_PI;
}

AnnotationFrame find_annotation_frame(const ColoredCloud& cloud, const std::vector<Pose>& camera_poses,
                                      const LevelConfig& config) {
  AnnotationFrame frame;
  if (!config.level || cloud.empty()) return frame;
  const std::vector<Eigen::Vector3f> points = sample(cloud);
  const Eigen::Vector3d viewpoint = mean_position(camera_poses, points);
  const double tolerance = std::max(0.01, 1.5 * config.voxel_size_m);
  Up up;
  if (config.up) {  // its planes give the floor's height only
    up = up_from_planes(points, config.up->normalized(), 10 * M_PI / 180, viewpoint, tolerance);
    up.direction = config.up->normalized();
    frame.method = "given";
  } else {
    up = up_from_planes(points, cameras_up(camera_poses), 50 * M_PI / 180, viewpoint, tolerance);
    refine_up(points, up, tolerance);
    frame.method = up.planes.empty() ? "cameras" : "support_plane";
  }
  const Eigen::Vector3d z = up.direction;
  for (const auto& plane : up.planes) frame.support_points += plane.inliers;
  // The origin: on the lowest horizontal plane holding at least a fifth of the largest's points (the
  // floor where it is seen, else the table), under the scene's centre; without planes, the lowest
  // points' height (the 2nd percentile).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::vector<double> heights;
  for (const auto& p : points) {
    centre += p.cast<double>();
    heights.push_back(z.dot(p.cast<double>()));
  }
  centre /= std::max<double>(1, static_cast<double>(points.size()));
  double ground = 0;
  if (!up.planes.empty()) {
    ground = INFINITY;
    const size_t largest = up.planes.front().inliers;
    for (const auto& plane : up.planes)
      if (plane.inliers * 5 >= largest) ground = std::min(ground, -plane.d / plane.normal.dot(z));
  } else if (!heights.empty()) {
    std::nth_element(heights.begin(), heights.begin() + static_cast<long>(heights.size() / 50), heights.end());
    ground = heights[heights.size() / 50];
  }
  const Eigen::Vector3d origin = centre + (ground - z.dot(centre)) * z;
  const Eigen::Vector3d x = x_axis(points, z, tolerance, &frame.x_axis);
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  frame.T_world_annotation = Pose::Identity();
  frame.T_world_annotation.linear() = R;
  frame.T_world_annotation.translation() = origin;
  return frame;
}

nlohmann::json to_json(const AnnotationFrame& frame) {
  const Eigen::Matrix4d m = frame.T_world_annotation.matrix();
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  const Eigen::Vector3d up = frame.T_world_annotation.linear().col(2);
  return {{"T_world_annotation", pose_to_json(frame.T_world_annotation)},
          {"matrix", rows},
          {"up_in_world", {up.x(), up.y(), up.z()}},
          {"method", frame.method},
          {"support_points", frame.support_points},
          {"x_axis", frame.x_axis},
          {"tilt_deg", frame.tilt_deg()}};
}

AnnotationFrame annotation_frame_from_json(const nlohmann::json& j) {
  AnnotationFrame frame;
  frame.T_world_annotation = pose_from_json(j.at("T_world_annotation"));
  frame.method = j.value("method", "none");
  frame.support_points = j.value("support_points", size_t{0});
  frame.x_axis = j.value("x_axis", "none");
  return frame;
}

}  // namespace olt
