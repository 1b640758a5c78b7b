// libolt_clouds.so: PCL's RANSAC plane finding (olt/reconstruct/plane_finder.h), from its sample
// consensus library alone: a model and RANSAC made per plane, as pcl::SACSegmentation makes them
// (so the planes are the ones it finds), without its segmentation library, which brings PCL's
// features, filters and search libraries (~30 MB of their relocated tables resident in every
// process that finds a floor).
#include <pcl/point_types.h>
#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_parallel_plane.h>
#include <pcl/sample_consensus/sac_model_perpendicular_plane.h>
#include <pcl/sample_consensus/sac_model_plane.h>

#include <cmath>
#include <memory>
#include <vector>

#include "entry_points.h"

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Model = pcl::SampleConsensusModel<pcl::PointXYZ>;

// The model SACSegmentation makes for the query (the same type, axis and angle): a fresh one per
// plane, whose generator starts from PCL's constant seed.
Model::Ptr plane_model(const Cloud::ConstPtr& cloud, const olt::PlaneQuery& query) {
  if (query.max_angle_rad >= M_PI / 2) return std::make_shared<pcl::SampleConsensusModelPlane<pcl::PointXYZ>>(cloud);
  const auto constrained = [&](auto model) -> Model::Ptr {  // the axis and angle, where given
    const Eigen::Vector3f axis = query.axis.cast<float>();
    if (axis != Eigen::Vector3f::Zero()) model->setAxis(axis);
    if (query.max_angle_rad != 0.0) model->setEpsAngle(query.max_angle_rad);
    return model;
  };
  if (query.perpendicular)
    return constrained(std::make_shared<pcl::SampleConsensusModelPerpendicularPlane<pcl::PointXYZ>>(cloud));
  return constrained(std::make_shared<pcl::SampleConsensusModelParallelPlane<pcl::PointXYZ>>(cloud));
}

// The points of `cloud` that are not `inliers`, in their order.
Cloud::Ptr without(const Cloud& cloud, const pcl::Indices& inliers) {
  std::vector<char> taken(cloud.size(), 0);
  for (const auto i : inliers) taken[static_cast<size_t>(i)] = 1;
  auto rest = std::make_shared<Cloud>();
  rest->reserve(cloud.size() - inliers.size());
  for (size_t i = 0; i < cloud.size(); ++i)
    if (!taken[i]) rest->push_back(cloud[i]);
  return rest;
}

}  // namespace

void olt_find_planes(const std::vector<Eigen::Vector3f>& points, const olt::PlaneQuery& query,
                     std::vector<olt::Plane>& planes) {
  auto cloud = std::make_shared<Cloud>();
  cloud->reserve(points.size());
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  planes.clear();
  for (int k = 0; k < query.max_planes && cloud->size() >= query.min_inliers; ++k) {
    // RANSAC of at most 1,000 draws, then the coefficients refined on the inliers and the inliers
    // taken again within the distance of the refined plane (SACSegmentation's optimize step).
    const Model::Ptr model = plane_model(cloud, query);
    pcl::RandomSampleConsensus<pcl::PointXYZ> ransac(model, query.distance_m);
    ransac.setMaxIterations(1000);
    if (!ransac.computeModel(0)) break;
    pcl::Indices inliers;
    ransac.getInliers(inliers);
    Eigen::VectorXf coefficients(model->getModelSize()), refined(model->getModelSize());
    ransac.getModelCoefficients(coefficients);
    model->optimizeModelCoefficients(inliers, coefficients, refined);
    model->selectWithinDistance(refined, query.distance_m, inliers);
    if (inliers.size() < query.min_inliers || refined.size() != 4) break;
    olt::Plane plane;
    const Eigen::Vector3d n(refined[0], refined[1], refined[2]);
    plane.normal = n.normalized();
    plane.d = refined[3] / n.norm();
    plane.inliers = inliers.size();
    planes.push_back(plane);
    cloud = without(*cloud, inliers);
  }
}
