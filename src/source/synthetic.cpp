#include "olt/source/synthetic.h"

#include <cmath>
#include <limits>

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
bool hit_box(const Box& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double* t_hit,
             Eigen::Vector3d* normal_world) {
  const Pose inv = box.T_world_box.inverse();
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

}  // namespace

SyntheticScene make_synthetic_scene(const SyntheticConfig& config) {
  SyntheticScene scene;
  scene.config = config;
  const double f = 525.0 * config.width / 640.0;
  scene.camera = {config.width, config.height, f, f, (config.width - 1) / 2.0, (config.height - 1) / 2.0, {}};
  for (const auto& o : kObjects) {
    scene.objects.push_back(make_box(o, 0, 0));
    scene.annotations.push_back(make_box(o, kAnnotationMargin, kAnnotationLift));
  }
  // An arc of 100 degrees around the table at 2.2 m, eye height 1.45-1.55 m, gaze sweeping the room.
  for (int i = 0; i < config.frames; ++i) {
    const double s = config.frames > 1 ? static_cast<double>(i) / (config.frames - 1) : 0.0;
    const double angle = (-120.0 + 100.0 * s) * M_PI / 180.0;
    const Eigen::Vector3d eye(2.2 * std::cos(angle), 2.2 * std::sin(angle), 1.5 + 0.05 * std::sin(2 * M_PI * s));
    const Eigen::Vector3d target(0.3 * std::sin(3 * s), 0.3 * std::cos(2 * s), 0.55);
    scene.timestamps.push_back(1000.0 + i / config.rate_hz);
    scene.T_world_camera.push_back(look_at(eye, target));
  }
  return scene;
}

SyntheticFrame render_synthetic_frame(const SyntheticScene& scene, size_t index) {
  const Intrinsics& c = scene.camera;
  const Pose& T = scene.T_world_camera.at(index);
  SyntheticFrame frame{cv::Mat(c.height, c.width, CV_16UC1), cv::Mat(c.height, c.width, CV_8UC3),
                       cv::Mat(c.height, c.width, CV_16UC1)};
  const Eigen::Vector3d origin = T.translation();
#pragma omp parallel for schedule(dynamic, 8)
  for (int v = 0; v < c.height; ++v) {
    for (int u = 0; u < c.width; ++u) {
      // With d = R * (x, y, 1) the ray parameter is the z-depth in the camera frame.
      const Eigen::Vector3d d = T.linear() * Eigen::Vector3d((u - c.cx) / c.fx, (v - c.cy) / c.fy, 1.0);
      Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
      int surface = 0;
      double t = hit_room(origin, d, &normal, &surface);
      int object = -1;
      for (size_t k = 0; k < scene.objects.size(); ++k) {
        double tk;
        Eigen::Vector3d nk;
        if (hit_box(scene.objects[k], origin, d, &tk, &nk) && tk < t) {
          t = tk;
          normal = nk;
          object = static_cast<int>(k);
        }
      }
      const double units = std::round(t * scene.config.depth_scale);
      frame.depth.at<uint16_t>(v, u) = units > 65535 ? 0 : static_cast<uint16_t>(units);
      frame.object.at<uint16_t>(v, u) = static_cast<uint16_t>(object + 1);
      const cv::Vec3b base = object >= 0 ? kObjects[object].bgr : room_color(surface, origin + t * d);
      frame.color.at<cv::Vec3b>(v, u) = shade(base, normal);
    }
  }
  return frame;
}

}  // namespace olt
