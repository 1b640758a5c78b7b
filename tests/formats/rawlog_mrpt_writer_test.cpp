// A rawlog in the observation-only form, written with libmrpt itself: odometry as
// CObservationOdometry poses, a scan scanning left to right, and a 3D scan whose range image holds
// distances along the rays (range_is_depth false) with a sensor pose turned 90 degrees left.
// Built only where libmrpt is installed, in a test binary of its own (olt_tests_mrpt), so that the
// main one does not load MRPT's ~170 shared libraries at each start.
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <catch2/catch.hpp>
#include <opencv2/core.hpp>

#include "olt/formats/rawlog.h"
#include "support/temp_dir.h"

using namespace olt;

TEST_CASE("rawlog: the observation-only form, written by libmrpt, reads back in OLT's conventions") {
  olt::test::TempDir dir;
  const std::string file = (dir / "observations.rawlog").string();
  {
    mrpt::io::CFileGZOutputStream out(file);
    auto archive = mrpt::serialization::archiveFrom(out);
    for (int k = 0; k < 3; ++k) {
      auto odometry = mrpt::obs::CObservationOdometry::Create();
      odometry->timestamp = mrpt::Clock::fromDouble(100.0 + k);
      odometry->odometry = mrpt::poses::CPose2D(0.5 * k, 0.1 * k, 0.2 * k);
      archive << *odometry;
    }
    auto scan = mrpt::obs::CObservation2DRangeScan::Create();
    scan->timestamp = mrpt::Clock::fromDouble(100.5);
    scan->sensorLabel = "LASER";
    scan->aperture = static_cast<float>(M_PI / 2);
    scan->rightToLeft = false;
    scan->maxRange = 10;
    scan->sensorPose = mrpt::poses::CPose3D(0.2, 0, 0.3, 0, 0, 0);
    scan->resizeScan(3);
    for (size_t i = 0; i < 3; ++i) {
      scan->setScanRange(i, 1.0f + static_cast<float>(i));
      scan->setScanRangeValidity(i, i != 1);
    }
    archive << *scan;
    auto rgbd = mrpt::obs::CObservation3DRangeScan::Create();
    rgbd->timestamp = mrpt::Clock::fromDouble(101.0);
    rgbd->sensorLabel = "CAM";
    rgbd->sensorPose = mrpt::poses::CPose3D(0.1, 0, 1.0, M_PI / 2, 0, 0);
    rgbd->hasRangeImage = true;
    rgbd->range_is_depth = false;
    rgbd->rangeUnits = 0.001f;
    rgbd->cameraParams.ncols = 4;
    rgbd->cameraParams.nrows = 3;
    rgbd->cameraParams.fx(2);
    rgbd->cameraParams.fy(2);
    rgbd->cameraParams.cx(1);
    rgbd->cameraParams.cy(1);
    rgbd->cameraParamsIntensity = rgbd->cameraParams;
    rgbd->rangeImage.setZero(3, 4);
    rgbd->rangeImage(1, 1) = 2000;  // on the optical axis: depth 2 m
    rgbd->rangeImage(1, 3) = 3000;  // 45 degrees off it (x = (3 - 1) / 2 = 1): depth 3 / sqrt(2)
    archive << *rgbd;
  }
  std::vector<LaserScan> scans;
  std::vector<OdometrySample> odometry;
  std::vector<RawlogRgbd> rgbd;
  RawlogVisitor visit;
  visit.scan = [&](LaserScan&& s, const std::string& label) {
    CHECK(label == "LASER");
    scans.push_back(std::move(s));
  };
  visit.odometry = [&](const OdometrySample& o) { odometry.push_back(o); };
  visit.rgbd = [&](RawlogRgbd&& o) { rgbd.push_back(std::move(o)); };
  read_rawlog(file, visit);
  REQUIRE(odometry.size() == 3);
  CHECK(odometry[2].timestamp == Approx(102.0));
  CHECK(odometry[2].pose.translation().isApprox(Eigen::Vector2d(1.0, 0.2), 1e-6));
  CHECK(heading(odometry[2].pose) == Approx(0.4));
  REQUIRE(scans.size() == 1);
  CHECK_FALSE(scans[0].right_to_left);
  CHECK(scans[0].ray_angle(0) == Approx(M_PI / 4));  // left to right: the first ray on the left
  CHECK(scans[0].valid == std::vector<uint8_t>{1, 0, 1});
  CHECK(scans[0].ranges[2] == Approx(3.0f));
  CHECK(scans[0].T_robot_laser.translation().isApprox(Eigen::Vector3d(0.2, 0, 0.3), 1e-6));
  REQUIRE(rgbd.size() == 1);
  const RawlogRgbd& o = rgbd[0];
  CHECK(o.sensor == "CAM");
  CHECK(o.depth.at<uint16_t>(1, 1) == 2000);
  CHECK(o.depth.at<uint16_t>(1, 3) == std::lround(3000 / std::sqrt(2.0)));
  CHECK(o.depth.at<uint16_t>(0, 0) == 0);
  CHECK(o.color.empty());
  // Turned 90 degrees left: the optical axis is the robot's +y; facing +y, the image's right
  // (optical x) is the robot's +x, and its down (optical y) the robot's -z.
  CHECK((o.T_robot_sensor.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY(), 1e-9));
  CHECK((o.T_robot_sensor.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitX(), 1e-9));
  CHECK((o.T_robot_sensor.linear() * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ(), 1e-9));
  CHECK(o.T_robot_sensor.translation().isApprox(Eigen::Vector3d(0.1, 0, 1.0), 1e-9));
}
