// The original Object Labeling Toolkit's way to label depth points (PCL CropHull on each box's
// convex hull, per frame), timed on the frames and boxes of the exchange file that
// olt_bench_propagation writes. Prints one JSON line: median milliseconds per frame (building the
// world-frame cloud, then hull + crop for every box; PNG decoding excluded) and, per frame, the
// number of points inside each box, for the agreement check.
//   olt_bench_crophull EXCHANGE.json [--frames N]      (N: first frames to run, default 3: it is slow)
#include <pcl/filters/crop_hull.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/convex_hull.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s EXCHANGE.json [--frames N]\n", argv[0]);
    return 2;
  }
  const size_t max_frames = argc >= 4 && std::string(argv[2]) == "--frames" ? std::stoul(argv[3]) : 3;
  std::ifstream in(argv[1]);
  const nlohmann::json x = nlohmann::json::parse(in);
  const auto& k = x["intrinsics"];
  const double fx = k["fx"], fy = k["fy"], cx = k["cx"], cy = k["cy"], scale = x["depth_scale"];
  const double near = x["min_depth_m"], far = x["max_depth_m"];

  // Each box's 8 corners in the world frame.
  std::vector<pcl::PointCloud<pcl::PointXYZ>::Ptr> corners;
  for (const auto& b : x["boxes"]) {
    Eigen::Matrix3d R;
    for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = b["rotation"][i];
    const Eigen::Vector3d c(b["center"][0], b["center"][1], b["center"][2]);
    const Eigen::Vector3d half(b["size"][0].get<double>() / 2, b["size"][1].get<double>() / 2,
                               b["size"][2].get<double>() / 2);
    auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d local((i & 1 ? 1 : -1) * half.x(), (i & 2 ? 1 : -1) * half.y(),
                                  (i & 4 ? 1 : -1) * half.z());
      const Eigen::Vector3d p = c + R * local;
      cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
    }
    corners.push_back(cloud);
  }

  std::vector<double> ms;
  nlohmann::json inside = nlohmann::json::array();
  const auto& frames = x["frames"];
  for (size_t f = 0; f < std::min(max_frames, frames.size()); ++f) {
    const cv::Mat depth = cv::imread(frames[f]["depth"].get<std::string>(), cv::IMREAD_UNCHANGED);
    Eigen::Matrix4d T;
    for (int i = 0; i < 16; ++i) T(i / 4, i % 4) = frames[f]["T_world_sensor"][i];
    const auto start = std::chrono::steady_clock::now();
    auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    for (int v = 0; v < depth.rows; ++v)
      for (int u = 0; u < depth.cols; ++u) {
        const double z = depth.at<uint16_t>(v, u) / scale;
        if (depth.at<uint16_t>(v, u) == 0 || z < near || z > far) continue;
        const Eigen::Vector4d p = T * Eigen::Vector4d((u - cx) * z / fx, (v - cy) * z / fy, z, 1);
        cloud->push_back(
            pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
      }
    nlohmann::json counts = nlohmann::json::array();
    for (const auto& box : corners) {
      pcl::ConvexHull<pcl::PointXYZ> hull;
      hull.setInputCloud(box);
      hull.setDimension(3);
      pcl::PointCloud<pcl::PointXYZ>::Ptr hull_points = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
      std::vector<pcl::Vertices> polygons;
      hull.reconstruct(*hull_points, polygons);
      pcl::CropHull<pcl::PointXYZ> crop;
      crop.setHullCloud(hull_points);
      crop.setHullIndices(polygons);
      crop.setDim(3);
      crop.setInputCloud(cloud);
      pcl::Indices kept;
      crop.filter(kept);
      counts.push_back(kept.size());
    }
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    inside.push_back(counts);
  }
  if (ms.empty()) {
    std::fprintf(stderr, "%s: no frames to label\n", argv[1]);
    return 2;
  }
  std::sort(ms.begin(), ms.end());
  std::printf("%s\n",
              nlohmann::json{
                  {"name", "pcl_crophull"}, {"frames", ms.size()}, {"median_ms", ms[ms.size() / 2]}, {"inside", inside}}
                  .dump()
                  .c_str());
  return 0;
}
