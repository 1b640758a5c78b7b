#include "olt/propagate/propagate.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace olt {
namespace {

// The image rectangle that can contain pixels of `box` (projected corners, conservatively the
// whole image when a corner lies behind the camera or distortion makes projection unreliable).
cv::Rect candidate_rect(const Box& box, const SensorCalibration& cal, const Pose& T_sensor_world) {
  const cv::Rect image(0, 0, cal.depth.width, cal.depth.height);
  if (cal.depth.distorted()) return image;
  double u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
  int behind = 0;
  for (const auto& corner : box_corners(box)) {
    const Eigen::Vector3d p = T_sensor_world * corner;
    if (p.z() <= 1e-3) {
      ++behind;
      continue;
    }
    Eigen::Vector2d px;
    project(cal.depth, p, &px);
    u0 = std::min(u0, px.x());
    v0 = std::min(v0, px.y());
    u1 = std::max(u1, px.x());
    v1 = std::max(v1, px.y());
  }
  if (behind == 8) return {};
  if (behind > 0) return image;
  const cv::Rect rect(cv::Point(static_cast<int>(std::floor(u0)) - 1, static_cast<int>(std::floor(v0)) - 1),
                      cv::Point(static_cast<int>(std::ceil(u1)) + 2, static_cast<int>(std::ceil(v1)) + 2));
  return rect & image;
}

}  // namespace

std::vector<LabeledBox> prioritized_boxes(const std::vector<Box>& boxes, const LabelMap& map) {
  std::vector<LabeledBox> out;
  for (const auto& b : boxes) out.push_back({b, map.class_id(b.label), map.instance_id(b.instance)});
  std::sort(out.begin(), out.end(), [](const LabeledBox& a, const LabeledBox& b) {
    const double va = a.box.volume(), vb = b.box.volume();
    return va != vb ? va < vb : a.box.id < b.box.id;
  });
  return out;
}

FrameLabels label_depth_image(const cv::Mat& depth, const SensorCalibration& cal,
                              const std::vector<Eigen::Vector2f>& rays, const Pose& T_world_sensor,
                              const std::vector<LabeledBox>& boxes) {
  const int width = depth.cols, height = depth.rows;
  FrameLabels out{cv::Mat(height, width, CV_16UC1, cv::Scalar(kNoDepth)),
                  cv::Mat(height, width, CV_16UC1, cv::Scalar(kNoDepth)),
                  0,
                  0,
                  0,
                  std::vector<int>(boxes.size(), 0)};
  // Back-project once: the point of every valid pixel in the sensor frame.
  std::vector<Eigen::Vector3f> points(static_cast<size_t>(width) * height);
  std::vector<uint8_t> hits(points.size(), 0);
  for (int v = 0; v < height; ++v) {
    const uint16_t* row = depth.ptr<uint16_t>(v);
    for (int u = 0; u < width; ++u) {
      const float z = static_cast<float>(row[u] / cal.depth_scale);
      if (row[u] == 0 || z < cal.min_depth_m || z > cal.max_depth_m) continue;
      const size_t i = static_cast<size_t>(v) * width + u;
      points[i] = Eigen::Vector3f(rays[i].x() * z, rays[i].y() * z, z);
      out.class_ids.at<uint16_t>(v, u) = kUnlabeled;
      out.instance_ids.at<uint16_t>(v, u) = kUnlabeled;
      ++out.valid_pixels;
    }
  }
  const Pose T_sensor_world = T_world_sensor.inverse();
  for (size_t k = 0; k < boxes.size(); ++k) {
    const Box& box = boxes[k].box;
    const cv::Rect rect = candidate_rect(box, cal, T_sensor_world);
    if (rect.empty()) continue;
    const Pose T_box_sensor = box.T_world_box.inverse() * T_world_sensor;
    const Eigen::Matrix3f R = T_box_sensor.linear().cast<float>();
    const Eigen::Vector3f t = T_box_sensor.translation().cast<float>();
    const Eigen::Vector3f half = (0.5 * box.size).cast<float>();
    for (int v = rect.y; v < rect.y + rect.height; ++v) {
      uint16_t* classes = out.class_ids.ptr<uint16_t>(v);
      uint16_t* instances = out.instance_ids.ptr<uint16_t>(v);
      for (int u = rect.x; u < rect.x + rect.width; ++u) {
        if (classes[u] == kNoDepth) continue;
        const size_t i = static_cast<size_t>(v) * width + u;
        const Eigen::Vector3f p = R * points[i] + t;
        if (std::abs(p.x()) > half.x() || std::abs(p.y()) > half.y() || std::abs(p.z()) > half.z()) continue;
        if (++hits[i] > 1) {
          if (hits[i] == 2) ++out.ambiguous_pixels;
          hits[i] = 2;
          continue;
        }
        classes[u] = boxes[k].class_id;
        instances[u] = boxes[k].instance_id;
        ++out.box_pixels[k];
        ++out.labeled_pixels;
      }
    }
  }
  return out;
}

cv::Mat render_overlay(const cv::Mat& color_bgr, const cv::Mat& depth, const FrameLabels& labels, const LabelMap& map,
                       const std::vector<LabeledBox>& boxes, const SensorCalibration& cal, const Pose& T_world_sensor) {
  cv::Mat base;
  if (!color_bgr.empty()) {
    cv::resize(color_bgr, base, depth.size(), 0, 0, cv::INTER_AREA);
  } else {
    cv::Mat grey;
    depth.convertTo(grey, CV_8U, 255.0 / (cal.max_depth_m * cal.depth_scale));
    cv::cvtColor(grey, base, cv::COLOR_GRAY2BGR);
  }
  cv::Mat overlay = base.clone();
  for (int v = 0; v < overlay.rows; ++v) {
    for (int u = 0; u < overlay.cols; ++u) {
      const uint16_t id = labels.class_ids.at<uint16_t>(v, u);
      cv::Vec3b& px = overlay.at<cv::Vec3b>(v, u);
      if (id == kNoDepth) {
        px = cv::Vec3b(px[0] / 3, px[1] / 3, px[2] / 3);  // darken: no depth, no label possible
      } else if (const LabelClass* c = map.find_class(id); c && id != kUnlabeled) {
        px = cv::Vec3b((px[0] + c->color[2]) / 2, (px[1] + c->color[1]) / 2, (px[2] + c->color[0]) / 2);
      }
    }
  }
  // Box outlines, clipped to the space in front of the camera.
  const Pose T_sensor_world = T_world_sensor.inverse();
  static const int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                    {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (const auto& lb : boxes) {
    const auto corners = box_corners(lb.box);
    const auto color = class_color(lb.class_id);
    for (const auto& e : kEdges) {
      Eigen::Vector3d a = T_sensor_world * corners[e[0]], b = T_sensor_world * corners[e[1]];
      constexpr double kNear = 0.05;
      if (a.z() < kNear && b.z() < kNear) continue;
      if (a.z() < kNear) a = b + (a - b) * ((b.z() - kNear) / (b.z() - a.z()));
      if (b.z() < kNear) b = a + (b - a) * ((a.z() - kNear) / (a.z() - b.z()));
      Eigen::Vector2d pa, pb;
      project(cal.depth, a, &pa);
      project(cal.depth, b, &pb);
      cv::line(overlay, cv::Point2d(pa.x(), pa.y()), cv::Point2d(pb.x(), pb.y()),
               cv::Scalar(color[2], color[1], color[0]), 1, cv::LINE_AA);
    }
  }
  return overlay;
}

}  // namespace olt
