#include "olt/reconstruct/fusion.h"

#include <catch2/catch.hpp>

using namespace olt;

TEST_CASE("voxel fusion averages position and colour per voxel - in a fixed order") {
  VoxelFusion fusion(0.1);
  fusion.add({0.01, 0.02, 0.03}, {10, 20, 30});
  fusion.add({0.05, 0.06, 0.07}, {30, 40, 51});
  fusion.add({-0.05, 0.0, 0.0}, {0, 0, 0});
  const auto cloud = fusion.cloud();
  REQUIRE(cloud.size() == 2);
  const auto& p = cloud[1].x > 0 ? cloud[1] : cloud[0];
  CHECK(p.x == Approx(0.03));
  CHECK(p.z == Approx(0.05));
  CHECK(int(p.b) == 20);
  CHECK(int(p.g) == 30);
  CHECK(int(p.r) == 41);  // (30 + 51) / 2 rounded half up
}

TEST_CASE("fusing one observation back-projects with the pose") {
  SensorCalibration cal;
  cal.depth = {3, 1, 1, 1, 1, 0, {}};
  cal.color = cal.depth;
  cal.depth_scale = 1000;
  cv::Mat depth(1, 3, CV_16UC1, cv::Scalar(1000));
  cv::Mat color(1, 3, CV_8UC3, cv::Scalar(1, 2, 3));
  VoxelFusion fusion(0.01);
  fuse_observation(fusion, depth, color, cal, pixel_rays(cal.depth), pose_from_xyz_ypr_deg({0, 0, 5, 0, 0, 0}), 1);
  const auto cloud = fusion.cloud();
  REQUIRE(cloud.size() == 3);
  for (const auto& p : cloud) {
    CHECK(p.z == Approx(6));  // 1 m in front of a camera at z = 5 looking along +z
    CHECK(int(p.r) == 3);
  }
}
