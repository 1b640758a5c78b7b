// libolt_clouds.so: PCL's RANSAC plane segmentation (olt/reconstruct/plane_finder.h).
#include <pcl/ModelCoefficients.h>
#include <pcl/filters/extract_indices.h>
#include <pcl/point_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <cmath>

#include "entry_points.h"

void olt_find_planes(const std::vector<Eigen::Vector3f>& points, const olt::PlaneQuery& query,
                     std::vector<olt::Plane>& planes) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points.size());
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  planes.clear();
  // PCL's RANSAC draws from a generator seeded with a constant: the same points give the same planes.
  pcl::SACSegmentation<pcl::PointXYZ> ransac;
  ransac.setOptimizeCoefficients(true);
  const bool any = query.max_angle_rad >= M_PI / 2;
  ransac.setModelType(any                   ? pcl::SACMODEL_PLANE
                      : query.perpendicular ? pcl::SACMODEL_PERPENDICULAR_PLANE
                                            : pcl::SACMODEL_PARALLEL_PLANE);
  ransac.setMethodType(pcl::SAC_RANSAC);
  ransac.setAxis(query.axis.cast<float>());
  ransac.setEpsAngle(query.max_angle_rad);
  ransac.setDistanceThreshold(query.distance_m);
  ransac.setMaxIterations(1000);
  for (int k = 0; k < query.max_planes && cloud->size() >= query.min_inliers; ++k) {
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coefficients;
    ransac.setInputCloud(cloud);
    ransac.segment(inliers, coefficients);
    if (inliers.indices.size() < query.min_inliers || coefficients.values.size() != 4) break;
    olt::Plane plane;
    const Eigen::Vector3d n(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
    plane.normal = n.normalized();
    plane.d = coefficients.values[3] / n.norm();
    plane.inliers = inliers.indices.size();
    planes.push_back(plane);
    pcl::ExtractIndices<pcl::PointXYZ> rest;
    rest.setInputCloud(cloud);
    rest.setIndices(std::make_shared<pcl::PointIndices>(inliers));
    rest.setNegative(true);
    auto left = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    rest.filter(*left);
    cloud = left;
  }
}
