#include "olt/laser/map_image.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "olt/core/image.h"

namespace olt {

std::string render_map_png(const std::vector<Eigen::Vector2d>& points, const std::vector<ScanPose>& poses,
                           double resolution_m, int max_size_px) {
  Eigen::Vector2d lo(0, 0), hi(0, 0);
  bool first = true;
  auto extend = [&](const Eigen::Vector2d& p) {
    lo = first ? p : lo.cwiseMin(p);
    hi = first ? p : hi.cwiseMax(p);
    first = false;
  };
  for (const auto& p : points) extend(p);
  for (const auto& p : poses) extend(p.T_map_robot.translation());
  const double margin = 1.0;
  lo -= Eigen::Vector2d(margin, margin);
  hi += Eigen::Vector2d(margin, margin);
  const Eigen::Vector2d extent = hi - lo;
  // Metres per pixel: the resolution asked for, finer for a small map (at least 800 pixels across),
  // coarser where the image would exceed its maximum size.
  const double longest = std::max(extent.x(), extent.y());
  const double scale = std::max(std::min(resolution_m, longest / 800), longest / max_size_px);
  const int width = std::max(1, static_cast<int>(std::ceil(extent.x() / scale)));
  const int height = std::max(1, static_cast<int>(std::ceil(extent.y() / scale)));
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  auto pixel = [&](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>((p.x() - lo.x()) / scale), static_cast<int>((hi.y() - p.y()) / scale));
  };
  for (const auto& p : points) {
    const cv::Point q = pixel(p);
    if (q.x >= 0 && q.y >= 0 && q.x + 1 < width && q.y + 1 < height)
      image(cv::Rect(q.x, q.y, 2, 2)).setTo(cv::Scalar(0, 0, 0));
  }
  for (size_t i = 1; i < poses.size(); ++i) {
    const cv::Scalar colour = poses[i].valid ? cv::Scalar(200, 90, 20) : cv::Scalar(30, 30, 220);
    cv::line(image, pixel(poses[i - 1].T_map_robot.translation()), pixel(poses[i].T_map_robot.translation()), colour, 1,
             cv::LINE_AA);
  }
  for (const auto& p : poses)
    if (p.key) cv::circle(image, pixel(p.T_map_robot.translation()), 2, cv::Scalar(200, 90, 20), -1, cv::LINE_AA);
  if (!poses.empty())  // the start, green
    cv::circle(image, pixel(poses.front().T_map_robot.translation()), 5, cv::Scalar(40, 170, 40), 2, cv::LINE_AA);
  const int bar = static_cast<int>(1.0 / scale);
  cv::line(image, cv::Point(10, height - 10), cv::Point(10 + bar, height - 10), cv::Scalar(0, 0, 0), 2);
  cv::putText(image, "1 m", cv::Point(14 + bar, height - 6), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  return encode_png_fast(image);
}

}  // namespace olt
