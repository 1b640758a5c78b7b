// libolt_rawlog.so: MRPT rawlogs read through libmrpt.
// read_rawlog through libmrpt (mrpt-obs).
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "entry_points.h"
#include "olt/core/error.h"

namespace olt {
namespace {

Pose to_pose(const mrpt::poses::CPose3D& p) {
  mrpt::math::CMatrixDouble44 m;
  p.getHomogeneousMatrix(m);
  Pose T = Pose::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = m(r, c);
    T.translation()[r] = m(r, 3);
  }
  return T;
}

Intrinsics intrinsics(const mrpt::img::TCamera& c) {
  Intrinsics k;
  k.width = static_cast<int>(c.ncols);
  k.height = static_cast<int>(c.nrows);
  k.fx = c.fx();
  k.fy = c.fy();
  k.cx = c.cx();
  k.cy = c.cy();
  k.distortion = {c.dist[0], c.dist[1], c.dist[2], c.dist[3], c.dist[4]};
  return k;
}

LaserScan to_scan(const mrpt::obs::CObservation2DRangeScan& o, int index) {
  LaserScan s;
  s.index = index;
  s.timestamp = mrpt::Clock::toDouble(o.timestamp);
  s.T_robot_laser = to_pose(o.sensorPose);
  s.aperture_rad = o.aperture;
  s.right_to_left = o.rightToLeft;
  s.max_range_m = o.maxRange;
  const size_t n = o.getScanSize();
  s.ranges.resize(n);
  s.valid.resize(n);
  for (size_t k = 0; k < n; ++k) {
    s.ranges[k] = o.getScanRange(k);
    s.valid[k] = o.getScanRangeValidity(k);
  }
  return s;
}

RawlogRgbd to_rgbd(const mrpt::obs::CObservation3DRangeScan& o, const std::string& file) {
  o.load();  // externally stored images
  if (!o.hasRangeImage)
    throw InputError(file, "3D range scan '" + o.sensorLabel + "' at " +
                               std::to_string(mrpt::Clock::toDouble(o.timestamp)) + " has no range image");
  RawlogRgbd r;
  r.sensor = o.sensorLabel.empty() ? "rgbd" : o.sensorLabel;
  r.timestamp = mrpt::Clock::toDouble(o.timestamp);
  r.depth_scale = 1.0 / o.rangeUnits;
  r.depth_intrinsics = intrinsics(o.cameraParams);
  r.color_intrinsics = intrinsics(o.cameraParamsIntensity);
  const int rows = static_cast<int>(o.rangeImage.rows()), cols = static_cast<int>(o.rangeImage.cols());
  r.depth = cv::Mat(rows, cols, CV_16UC1);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      double value = o.rangeImage(v, u);
      if (!o.range_is_depth && value > 0) {  // a distance along the ray: to depth along the optical axis
        const double x = (u - r.depth_intrinsics.cx) / r.depth_intrinsics.fx;
        const double y = (v - r.depth_intrinsics.cy) / r.depth_intrinsics.fy;
        value /= std::sqrt(1 + x * x + y * y);
      }
      r.depth.at<uint16_t>(v, u) = static_cast<uint16_t>(std::lround(value));
    }
  if (o.hasIntensityImage) {
    cv::Mat image = o.intensityImage.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    if (image.channels() == 1)
      cv::cvtColor(image, r.color, cv::COLOR_GRAY2BGR);
    else
      image.copyTo(r.color);
  }
  // MRPT gives the depth camera's pose in its camera frame and the intensity camera's pose (an
  // optical frame) relative to it.
  r.T_robot_sensor = to_pose(o.sensorPose) * mrpt_camera_from_optical();
  r.T_color_depth = to_pose(o.relativePoseIntensityWRTDepth).inverse() * mrpt_camera_from_optical();
  return r;
}

}  // namespace

}  // namespace olt

void olt_rawlog_read(const std::string& file, const olt::RawlogVisitor& visit) {
  using namespace olt;
  if (!std::filesystem::is_regular_file(file)) throw InputError(file, "not found");
  mrpt::img::CImage::setImagesPathBase(mrpt::obs::CRawlog::detectImagesDirectory(file));
  mrpt::io::CFileGZInputStream stream;
  if (!stream.open(file)) throw InputError(file, "cannot be opened");
  auto archive = mrpt::serialization::archiveFrom(stream);
  mrpt::poses::CPose2D odometry;  // integrated from the action form's increments
  int scans = 0;
  size_t entry = 0;
  try {
    for (;;) {
      mrpt::obs::CActionCollection::Ptr actions;
      mrpt::obs::CSensoryFrame::Ptr frame;
      mrpt::obs::CObservation::Ptr single;
      if (!mrpt::obs::CRawlog::getActionObservationPairOrObservation(archive, actions, frame, single, entry)) break;
      if (actions) {
        if (auto move = actions->getActionByClass<mrpt::obs::CActionRobotMovement2D>()) {
          odometry = odometry + move->rawOdometryIncrementReading;
          if (visit.odometry)
            visit.odometry({mrpt::Clock::toDouble(move->timestamp), pose2(odometry.x(), odometry.y(), odometry.phi())});
        }
      }
      std::vector<mrpt::obs::CObservation::Ptr> observations;
      if (frame) observations.assign(frame->begin(), frame->end());
      if (single) observations.push_back(single);
      for (const auto& o : observations) {
        if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) {
          if (visit.scan) visit.scan(to_scan(*scan, scans), scan->sensorLabel);
          ++scans;
        } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
          if (visit.odometry)
            visit.odometry({mrpt::Clock::toDouble(odo->timestamp),
                            pose2(odo->odometry.x(), odo->odometry.y(), odo->odometry.phi())});
        } else if (auto rgbd = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o)) {
          if (visit.rgbd) visit.rgbd(to_rgbd(*rgbd, file));
          rgbd->unload();
        }
      }
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(file, "unreadable rawlog at entry " + std::to_string(entry) + ": " + e.what());
  }
}
