#include "olt/source/synthetic.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "olt/core/parallel.h"
#include "synthetic_parts.h"

namespace olt {
namespace {

constexpr double kRoomHalfX = 3.0, kRoomHalfY = 2.5, kRoomHeight = 2.7;  // metres
// Annotation boxes: 1 cm larger than the object on every side and above, and 5 mm above its
// bottom face, so floor or table-top points under an object stay outside its box.
constexpr double kAnnotationMargin = 0.01, kAnnotationLift = 0.005;

struct ObjectSpec {
  const char* label;
  const char* instance;
  double x, y, z_bottom, sx, sy, sz, yaw_deg;
  cv::Vec3b bgr;
};

// A desk scene: a table with a monitor, a box and a book on it; a cabinet, a chair and a bin.
const ObjectSpec kObjects[] = {
    {"table", "table_1", 0.0, 0.0, 0.0, 1.2, 0.7, 0.74, 10, {60, 110, 160}},
    {"monitor", "monitor_1", 0.02, 0.18, 0.74, 0.52, 0.06, 0.34, 10, {40, 40, 40}},
    {"box", "box_1", -0.38, -0.12, 0.74, 0.28, 0.22, 0.18, 35, {90, 160, 210}},
    {"book", "book_1", 0.3, -0.15, 0.74, 0.22, 0.16, 0.04, -25, {50, 50, 190}},
    {"cabinet", "cabinet_1", -1.3, 1.1, 0.0, 0.5, 0.45, 1.0, -20, {170, 170, 120}},
    {"chair", "chair_1", 0.95, -0.75, 0.0, 0.45, 0.45, 0.9, 30, {140, 60, 60}},
    {"bin", "bin_1", 1.2, 0.9, 0.0, 0.3, 0.3, 0.4, 0, {60, 150, 60}},
};

// More furniture for the robot, which sees the whole room: a shelf against a wall and a plant.
const ObjectSpec kRobotObjects[] = {
    {"shelf", "shelf_1", 2.72, -1.0, 0.0, 0.3, 1.0, 1.8, 0, {90, 120, 150}},
    {"plant", "plant_1", -2.55, -2.05, 0.0, 0.35, 0.35, 0.9, 15, {40, 140, 60}},
};

Box make_box(const ObjectSpec& o, double margin, double lift) {
  Box b;
  b.label = o.label;
  b.instance = o.instance;
  b.id = o.instance;
  const double bottom = o.z_bottom + lift, top = o.z_bottom + o.sz + margin;
  b.size = Eigen::Vector3d(o.sx + 2 * margin, o.sy + 2 * margin, top - bottom);
  b.T_world_box = Pose::Identity();
  b.T_world_box.linear() = rotation_from_ypr_deg(o.yaw_deg, 0, 0);
  b.T_world_box.translation() = Eigen::Vector3d(o.x, o.y, 0.5 * (bottom + top));
  return b;
}

Pose look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Pose T = Pose::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

// Ray-box intersection by slabs in the box frame; returns the entry distance and outward normal.
bool hit_box(const Box& box, const Pose& inv, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double* t_hit,
             Eigen::Vector3d* normal_world) {
  const Eigen::Vector3d o = inv * origin, d = inv.linear() * dir, h = 0.5 * box.size;
  double t_near = -std::numeric_limits<double>::infinity(), t_far = std::numeric_limits<double>::infinity();
  int axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (std::abs(o[k]) > h[k]) return false;
      continue;
    }
    double t0 = (-h[k] - o[k]) / d[k], t1 = (h[k] - o[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) {
      t_near = t0;
      axis = k;
    }
    t_far = std::min(t_far, t1);
  }
  if (t_near > t_far || t_near <= 0 || axis < 0) return false;
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n[axis] = d[axis] > 0 ? -1 : 1;
  *t_hit = t_near;
  *normal_world = box.T_world_box.linear() * n;
  return true;
}

// The room seen from inside: the exit distance through the walls, floor or ceiling.
double hit_room(const Eigen::Vector3d& o, const Eigen::Vector3d& d, Eigen::Vector3d* normal, int* surface) {
  const double lo[3] = {-kRoomHalfX, -kRoomHalfY, 0}, hi[3] = {kRoomHalfX, kRoomHalfY, kRoomHeight};
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) continue;
    const double t = ((d[k] > 0 ? hi[k] : lo[k]) - o[k]) / d[k];
    if (t > 0 && t < best) {
      best = t;
      *normal = Eigen::Vector3d::Zero();
      (*normal)[k] = d[k] > 0 ? -1 : 1;
      *surface = 2 * k + (d[k] > 0 ? 1 : 0);
    }
  }
  return best;
}

cv::Vec3b shade(cv::Vec3b base, const Eigen::Vector3d& normal) {
  static const Eigen::Vector3d light = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const double k = 0.55 + 0.45 * std::max(0.0, normal.dot(light));
  return cv::Vec3b(cv::saturate_cast<uchar>(base[0] * k), cv::saturate_cast<uchar>(base[1] * k),
                   cv::saturate_cast<uchar>(base[2] * k));
}

cv::Vec3b room_color(int surface, const Eigen::Vector3d& p) {
  if (surface == 4) {  // floor: a 0.5 m checkerboard
    const bool dark = (static_cast<int>(std::floor(p.x() / 0.5)) + static_cast<int>(std::floor(p.y() / 0.5))) & 1;
    return dark ? cv::Vec3b(120, 130, 140) : cv::Vec3b(180, 190, 200);
  }
  if (surface == 5) return cv::Vec3b(235, 235, 235);  // ceiling
  static const cv::Vec3b walls[4] = {{200, 220, 230}, {210, 200, 190}, {190, 215, 200}, {220, 210, 225}};
  return walls[surface];
}

const ObjectSpec& object_spec(size_t k) {
  constexpr size_t n = sizeof(kObjects) / sizeof(kObjects[0]);
  return k < n ? kObjects[k] : kRobotObjects[k - n];
}

}  // namespace

RayTracer::RayTracer(const std::vector<Box>& objects) : objects_(objects) {
  for (const auto& box : objects) box_from_world_.push_back(box.T_world_box.inverse());
}

Hit RayTracer::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& d) const {
  Hit hit;
  hit.t = hit_room(origin, d, &hit.normal, &hit.surface);
  for (size_t k = 0; k < objects_.size(); ++k) {
    double tk;
    Eigen::Vector3d nk;
    if (hit_box(objects_[k], box_from_world_[k], origin, d, &tk, &nk) && tk < hit.t) {
      hit.t = tk;
      hit.normal = nk;
      hit.object = static_cast<int>(k);
    }
  }
  return hit;
}

namespace {

// A standard normal number that depends only on its arguments (splitmix64, Box-Muller): the same
// noise whatever the threads' order.
double normal_noise(uint64_t a, uint64_t b, uint64_t c) {
  auto mix = [](uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  };
  const uint64_t h1 = mix(a ^ mix(b ^ mix(c))), h2 = mix(h1);
  const double u1 = (static_cast<double>(h1 >> 11) + 0.5) / 9007199254740992.0;
  const double u2 = static_cast<double>(h2 >> 11) / 9007199254740992.0;
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
}

}  // namespace

SyntheticScene make_synthetic_scene(const SyntheticConfig& config) {
  SyntheticScene scene;
  scene.config = config;
  const double f = 525.0 * config.width / 640.0;
  scene.camera = {config.width, config.height, f, f, (config.width - 1) / 2.0, (config.height - 1) / 2.0, {}};
  const size_t objects = sizeof(kObjects) / sizeof(kObjects[0]) +
                         (config.cameras > 0 ? sizeof(kRobotObjects) / sizeof(kRobotObjects[0]) : 0);
  for (size_t k = 0; k < objects; ++k) {
    scene.objects.push_back(make_box(object_spec(k), 0, 0));
    scene.annotations.push_back(make_box(object_spec(k), kAnnotationMargin, kAnnotationLift));
  }
  if (config.cameras > 0) {
    std::mt19937 rng(config.seed);
    make_robot(scene, rng);
    return scene;
  }
  scene.sensors = {"rgbd"};
  scene.T_robot_camera = {Pose::Identity()};
  // An arc of 100 degrees around the table at 2.2 m, eye height 1.45-1.55 m, gaze sweeping the room;
  // s in [0, 1] from the first observation to the last.
  auto camera_at = [&](double s) {
    const double angle = (-120.0 + 100.0 * s) * M_PI / 180.0;
    const Eigen::Vector3d eye(2.2 * std::cos(angle), 2.2 * std::sin(angle), 1.5 + 0.05 * std::sin(2 * M_PI * s));
    const Eigen::Vector3d target(0.3 * std::sin(3 * s), 0.3 * std::cos(2 * s), 0.55);
    return look_at(eye, target);
  };
  const double s_per_second = config.frames > 1 ? config.rate_hz / (config.frames - 1) : 0.0;
  for (int i = 0; i < config.frames; ++i) {
    const double s = config.frames > 1 ? static_cast<double>(i) / (config.frames - 1) : 0.0;
    const double color_dt = i % 2 ? -config.color_dt_s : config.color_dt_s;
    scene.timestamps.push_back(kStartTime + i / config.rate_hz);
    scene.camera_of.push_back(0);
    scene.T_world_camera.push_back(camera_at(s));
    scene.color_dt_s.push_back(color_dt);
    scene.T_world_color.push_back(camera_at(s + color_dt * s_per_second));
  }
  return scene;
}

Pose synthetic_truth_frame(double tilt_deg) {
  Pose T = Pose::Identity();
  if (tilt_deg == 0) return T;
  const Eigen::Vector3d axis(std::cos(M_PI / 6), std::sin(M_PI / 6), 0);
  T.linear() = Eigen::AngleAxisd(tilt_deg * M_PI / 180, axis).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.4, -0.3, 0.2);
  return T;
}

SyntheticFrame render_synthetic_frame(const SyntheticScene& scene, size_t index) {
  const Intrinsics& c = scene.camera;
  const Pose& T = scene.T_world_camera.at(index);
  SyntheticFrame frame{cv::Mat(c.height, c.width, CV_16UC1), cv::Mat(c.height, c.width, CV_8UC3),
                       cv::Mat(c.height, c.width, CV_16UC1)};
  const Eigen::Vector3d origin = T.translation();
  const bool noisy = scene.config.cameras > 0;
  // The colour image from where the camera was at its own capture time (the same pose when in step).
  const Pose& T_color = scene.T_world_color.at(index);
  const bool apart = T_color.matrix() != T.matrix();
  const RayTracer rays(scene.objects);
  parallel_for(static_cast<size_t>(c.height), [&](size_t row) {
    const int v = static_cast<int>(row);
    for (int u = 0; u < c.width; ++u) {
      // With d = R * (x, y, 1) the ray parameter is the z-depth in the camera frame.
      const Eigen::Vector3d d = T.linear() * Eigen::Vector3d((u - c.cx) / c.fx, (v - c.cy) / c.fy, 1.0);
      const Hit hit = rays.cast(origin, d);
      double z = hit.t;
      if (noisy) {  // a structured-light camera's noise: 1.2 mm + 1.9 mm (z - 0.4 m)^2 (Nguyen et al. 2012)
        z += (0.0012 + 0.0019 * (z - 0.4) * (z - 0.4)) *
             normal_noise(scene.config.seed, index, static_cast<uint64_t>(v) * 65536 + static_cast<uint64_t>(u));
      }
      const double units = std::round(z * scene.config.depth_scale);
      frame.depth.at<uint16_t>(v, u) = units > 65535 || units < 0 ? 0 : static_cast<uint16_t>(units);
      frame.object.at<uint16_t>(v, u) = static_cast<uint16_t>(hit.object + 1);
      const Eigen::Vector3d d_color =
          apart ? Eigen::Vector3d(T_color.linear() * Eigen::Vector3d((u - c.cx) / c.fx, (v - c.cy) / c.fy, 1.0)) : d;
      const Hit seen = apart ? rays.cast(T_color.translation(), d_color) : hit;
      const cv::Vec3b base = seen.object >= 0 ? object_spec(static_cast<size_t>(seen.object)).bgr
                                              : room_color(seen.surface, T_color.translation() + seen.t * d_color);
      frame.color.at<cv::Vec3b>(v, u) = shade(base, seen.normal);
    }
  });
  return frame;
}

}  // namespace olt
