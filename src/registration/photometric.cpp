#include "olt/registration/photometric.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace olt {

bool IntensityImage::pixel(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* jacobian) const {
  Eigen::Vector2d full;
  if (!project(camera, p, &full, jacobian)) return false;
  // Each halving (cv::pyrDown) keeps the even pixels: reduced pixel i is full pixel scale * i.
  *uv = full / scale;
  if (jacobian) *jacobian /= scale;
  return true;
}

IntensityImage make_intensity_image(const cv::Mat& image, const Intrinsics& camera, int halvings) {
  if (image.type() != CV_8UC3 && image.type() != CV_8UC1)
    throw std::invalid_argument("make_intensity_image: expected an 8-bit BGR or grey image");
  if (halvings < 0 || halvings > 4) throw std::invalid_argument("make_intensity_image: halvings must be 0 to 4");
  IntensityImage out;
  out.camera = camera;
  out.scale = 1 << halvings;
  cv::Mat grey;
  if (image.channels() == 3)
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else
    grey = image;
  cv::Mat reduced;
  grey.convertTo(reduced, CV_32F, 1.0 / 255);
  // Smoothed before each reduction (cv::pyrDown) and once more at the reduced size: a wider basin
  // for the few-pixel errors the geometric term leaves.
  for (int i = 0; i < halvings; ++i) cv::pyrDown(reduced, reduced);
  cv::GaussianBlur(reduced, out.intensity, cv::Size(5, 5), 1.0);
  cv::Sobel(out.intensity, out.gradient_x, CV_32F, 1, 0, 3, 1.0 / 8);
  cv::Sobel(out.intensity, out.gradient_y, CV_32F, 0, 1, 3, 1.0 / 8);
  return out;
}

bool sample(const cv::Mat& image, const Eigen::Vector2d& uv, float* value) {
  const double u = uv.x(), v = uv.y();
  if (!(u >= 0 && v >= 0 && u < image.cols - 1 && v < image.rows - 1)) return false;
  const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
  const float a = static_cast<float>(u - u0), b = static_cast<float>(v - v0);
  const float* r0 = image.ptr<float>(v0) + u0;
  const float* r1 = image.ptr<float>(v0 + 1) + u0;
  *value = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
  return true;
}

PhotometricPoints select_photometric_points(const std::vector<Eigen::Vector3d>& depth_points,
                                            const IntensityImage& image, const Pose& T_color_depth,
                                            double min_gradient) {
  PhotometricPoints out;
  const double min2 = min_gradient * min_gradient;
  for (const auto& p : depth_points) {
    Eigen::Vector2d uv;
    float i, gx, gy;
    if (!image.pixel(T_color_depth * p, &uv) || !sample(image.intensity, uv, &i) ||
        !sample(image.gradient_x, uv, &gx) || !sample(image.gradient_y, uv, &gy))
      continue;
    if (static_cast<double>(gx) * gx + static_cast<double>(gy) * gy < min2) continue;
    out.points.push_back(p);
    out.intensities.push_back(i);
  }
  return out;
}

}  // namespace olt
