// An independent check on real annotation (SUN RGB-D, ../shared/data/sunrgbd_samples): each
// object's human-drawn 3D box is propagated through the real depth, and the rectangle around its
// labeled pixels is compared with the object's independently human-drawn 2D box. The naive
// alternative, the rectangle around the box's projected corners, is scored the same way.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "olt/core/image.h"
#include "olt/propagate/propagate.h"
#include "support/temp_dir.h"

using namespace olt;
namespace fs = std::filesystem;

namespace {

struct Object {
  Box box;
  cv::Rect2d annotated;  ///< the 2D box, pixels
};

std::vector<double> numbers(const std::string& line) {
  std::istringstream in(line);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

double iou(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double inter = (a & b).area();
  return inter / (a.area() + b.area() - inter);
}

}  // namespace

TEST_CASE("SUN RGB-D: rectangles of propagated labels match the annotated 2D boxes better than projected corners") {
  const fs::path data = olt::test::shared_data("sunrgbd_samples");
  if (data.empty()) {
    WARN("skipped: ../shared/data/sunrgbd_samples is absent");
    return;
  }
  std::vector<double> ours, naive;
  for (const char* frame : {"000001", "000002", "000003", "000004"}) {
    // calib: Rtilt and K, each 3x3 column-major. p_cam = flip(Rtilt^T p_upright), flip(x, y, z) = (x, -z, y).
    std::ifstream calib(data / "calib" / (std::string(frame) + ".txt"));
    std::string line1, line2;
    std::getline(calib, line1);
    std::getline(calib, line2);
    const auto r = numbers(line1), k = numbers(line2);
    REQUIRE(r.size() == 9);
    REQUIRE(k.size() == 9);
    Eigen::Matrix3d Rtilt, flip;
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < 3; ++row) Rtilt(row, c) = r[c * 3 + row];
    flip << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    Pose T_world_sensor = Pose::Identity();  // world: the upright frame the boxes are given in
    T_world_sensor.linear() = (flip * Rtilt.transpose()).inverse();

    const cv::Mat depth = read_grey16(data / "depth" / (std::string(frame) + ".png"));
    SensorCalibration cal;
    cal.depth = {depth.cols, depth.rows, k[0], k[4], k[6], k[7], {}};
    cal.color = cal.depth;
    cal.depth_scale = 1000;
    cal.min_depth_m = 0.1;
    cal.max_depth_m = 10;

    // label: class xmin ymin w h  cx cy cz  half sizes (w l h)  heading vector (ox oy); x-extent 2l,
    // y-extent 2w, rotated about z by atan2(oy, ox) (votenet's convention).
    std::vector<Object> objects;
    std::ifstream labels_file(data / "label" / (std::string(frame) + ".txt"));
    for (std::string line; std::getline(labels_file, line);) {
      std::istringstream in(line);
      std::string name;
      in >> name;
      const auto v = numbers(line.substr(name.size()));
      REQUIRE(v.size() == 12);
      Object o;
      o.box.id = o.box.instance = name + "_" + std::to_string(objects.size());
      o.box.label = name;
      o.box.T_world_box.translation() = Eigen::Vector3d(v[4], v[5], v[6]);
      o.box.T_world_box.linear() =
          Eigen::AngleAxisd(std::atan2(v[11], v[10]), Eigen::Vector3d::UnitZ()).toRotationMatrix();
      o.box.size = Eigen::Vector3d(2 * v[8], 2 * v[7], 2 * v[9]);
      o.annotated = cv::Rect2d(v[0], v[1], v[2], v[3]);
      objects.push_back(o);
    }
    std::vector<Box> boxes;
    for (const auto& o : objects) boxes.push_back(o.box);
    const LabelMap map = make_label_map(boxes, {});
    const auto ordered = prioritized_boxes(boxes, map);
    const FrameLabels labels = label_depth_image(depth, cal, make_depth_view(cal.depth), T_world_sensor, ordered);
    const cv::Rect2d image(0, 0, depth.cols, depth.rows);
    for (const auto& o : objects) {
      size_t k_ordered = 0;
      while (ordered[k_ordered].box.id != o.box.id) ++k_ordered;
      const cv::Rect labeled = labels.boxes[k_ordered].bbox;
      ours.push_back(labeled.empty() ? 0.0 : iou(cv::Rect2d(labeled), o.annotated));
      // Naive: the rectangle around the projected corners in front of the camera, within the image.
      double u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
      for (const auto& corner : box_corners(o.box)) {
        Eigen::Vector2d px;
        if (!project(cal.depth, T_world_sensor.inverse() * corner, &px)) continue;
        u0 = std::min(u0, px.x()), v0 = std::min(v0, px.y()), u1 = std::max(u1, px.x()), v1 = std::max(v1, px.y());
      }
      const cv::Rect2d corners = u0 <= u1 ? cv::Rect2d(u0, v0, u1 - u0, v1 - v0) & image : cv::Rect2d();
      naive.push_back(corners.area() > 0 ? iou(corners, o.annotated) : 0.0);
      std::printf("SUN RGB-D %s %-16s IoU with the annotated 2D box: labels %.3f, projected corners %.3f\n", frame,
                  o.box.label.c_str(), ours.back(), naive.back());
    }
  }
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / v.size();
  };
  std::printf("SUN RGB-D, %zu objects: mean IoU %.3f from propagated labels, %.3f from projected corners\n",
              ours.size(), mean(ours), mean(naive));
  CHECK(ours.size() >= 10);
  CHECK(mean(ours) > mean(naive));
}
