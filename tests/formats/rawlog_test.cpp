// Rawlog reading (libmrpt) checked against what MRPT's own `rawlog-edit` prints for the same files:
// values copied from its output, and, where rawlog-edit is installed (Debian mrpt-apps), its output
// parsed live for every entry.
#include "olt/formats/rawlog.h"

#include <catch2/catch.hpp>
#include <cstdio>
#include <regex>

#include "olt/core/fs.h"

using namespace olt;

namespace {

std::string shell_output(const std::string& command) {
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    for (size_t n; (n = fread(buffer, 1, sizeof(buffer), pipe)) > 0;) out.append(buffer, n);
    pclose(pipe);
  }
  return out;
}

bool have_rawlog_edit() { return std::system("command -v rawlog-edit > /dev/null 2>&1") == 0; }

struct Sena {
  std::vector<LaserScan> scans;
  std::vector<OdometrySample> odometry;
};

Sena read_sena(const fs::path& file) {
  Sena s;
  RawlogVisitor visit;
  visit.scan = [&](LaserScan&& scan, const std::string& label) {
    CHECK(label.empty());  // rawlog-edit: Sensor label: ''
    s.scans.push_back(std::move(scan));
  };
  visit.odometry = [&](const OdometrySample& o) { s.odometry.push_back(o); };
  read_rawlog(file.string(), visit);
  return s;
}

}  // namespace

TEST_CASE("rawlog: the SENA loop's scans and odometry as rawlog-edit describes them") {
  const fs::path file = fs::path(OLT_SHARED_DATA_DIR) / "mrpt_laser/original_mrpt/sena_telecom_one_loop.rawlog";
  if (!rawlog_supported()) {
    WARN("skipped: built without libmrpt (format rawlog disabled)");
    return;
  }
  if (!fs::exists(file)) {
    WARN("skipped: " << file << " is absent (../shared/data)");
    return;
  }
  const Sena sena = read_sena(file);
  // rawlog-edit --info: 449 objects, 224 scans from 1137834225.973760 to 1137834284.788331.
  REQUIRE(sena.scans.size() == 224);
  REQUIRE(sena.odometry.size() == 224);
  CHECK(sena.scans.front().timestamp == Approx(1137834225.973760).margin(1e-6));
  CHECK(sena.scans.back().timestamp == Approx(1137834284.788331).margin(1e-6));
  // rawlog-edit --describe, first scan: (x,y,z,yaw,pitch,roll)=(0.7800,0.0000,0.3000,0,0,0),
  // Right->Left, 361 points, 50 invalid, maximum range 80.00 m, aperture 180.0 deg, raw values
  // starting 1.680 1.660 1.660 1.660 1.670 and ending 1.590 1.560 1.550.
  const LaserScan& first = sena.scans.front();
  CHECK(first.T_robot_laser.translation().isApprox(Eigen::Vector3d(0.78, 0, 0.3), 1e-6));
  CHECK(first.right_to_left);
  REQUIRE(first.ranges.size() == 361);
  CHECK(std::count(first.valid.begin(), first.valid.end(), 0) == 50);
  CHECK(first.max_range_m == Approx(80));
  CHECK(first.aperture_rad == Approx(M_PI));
  CHECK(first.ranges[0] == Approx(1.68f));
  CHECK(first.ranges[4] == Approx(1.67f));
  CHECK(first.ranges[358] == Approx(1.59f));
  CHECK(first.ranges[360] == Approx(1.55f));
  CHECK_FALSE(first.valid[21]);  // 81.870, the first invalid ray
  // The 100th odometry increment (0.284, -0.009, -2.26 deg): the integrated pose moves by it.
  const Pose2 step = sena.odometry[98].pose.inverse() * sena.odometry[99].pose;
  CHECK(step.translation().x() == Approx(0.284).margin(0.0005));
  CHECK(step.translation().y() == Approx(-0.009).margin(0.0005));
  CHECK(heading(step) * 180 / M_PI == Approx(-2.26).margin(0.005));

  if (!have_rawlog_edit()) {
    WARN("rawlog-edit not installed (mrpt-apps): compared with copied values only");
    return;
  }
  // Live: every scan's timestamp, and every odometry increment, as rawlog-edit prints them.
  const std::string stamps = shell_output("rawlog-edit --list-timestamps -i '" + file.string() +
                                          "' --text-file-output /dev/stdout 2>/dev/null");
  std::vector<double> listed;
  const std::regex stamp_line(R"((\d+\.\d+)\s+mrpt::obs::CObservation2DRangeScan)");
  for (std::sregex_iterator it(stamps.begin(), stamps.end(), stamp_line), end; it != end; ++it)
    listed.push_back(std::stod((*it)[1]));
  REQUIRE(listed.size() == sena.scans.size());
  for (size_t i = 0; i < listed.size(); ++i) CHECK(sena.scans[i].timestamp == Approx(listed[i]).margin(2e-6));
  const std::string described = shell_output("rawlog-edit --describe -i '" + file.string() + "' 2>/dev/null");
  const std::regex increment(R"(Actual odometry increment reading: \(([-\d.]+),([-\d.]+),([-\d.]+)deg\))");
  size_t k = 0;
  for (std::sregex_iterator it(described.begin(), described.end(), increment), end; it != end; ++it, ++k) {
    REQUIRE(k < sena.odometry.size());
    const Pose2 d = k == 0 ? sena.odometry[0].pose : sena.odometry[k - 1].pose.inverse() * sena.odometry[k].pose;
    CHECK(d.translation().x() == Approx(std::stod((*it)[1])).margin(0.0005));
    CHECK(d.translation().y() == Approx(std::stod((*it)[2])).margin(0.0005));
    CHECK(heading(d) * 180 / M_PI == Approx(std::stod((*it)[3])).margin(0.005));
  }
  CHECK(k == 224);
}

TEST_CASE("rawlog: an RGB-D observation (tests_rgbd.rawlog) as rawlog-edit describes it") {
  const fs::path file = "/usr/share/mrpt/datasets/tests_rgbd.rawlog";
  if (!rawlog_supported() || !fs::exists(file)) {
    WARN("skipped: needs libmrpt and " << file << " (Debian mrpt-common)");
    return;
  }
  std::vector<RawlogRgbd> seen;
  RawlogVisitor visit;
  visit.rgbd = [&](RawlogRgbd&& o) { seen.push_back(std::move(o)); };
  read_rawlog(file.string(), visit);
  REQUIRE(seen.size() == 1);
  const RawlogRgbd& o = seen[0];
  // rawlog-edit --describe: Sensor label 'OPENNI2', time_t 1462879443.617188454, rangeUnits 0.001,
  // depth camera 640x480 cx 314.64917 cy 240.16046 fx 572.88277 fy 542.73998 dist -4.747169e-03
  // -4.357976e-03, intensity camera cx 322.51599 fx 521.17923, intensity pose wrt depth
  // (-0.0015, 0.0000, 0.0006, -90deg, 0deg, -90deg), sensor pose identity.
  CHECK(o.sensor == "OPENNI2");
  CHECK(o.timestamp == Approx(1462879443.617188).margin(1e-6));
  CHECK(o.depth_scale == Approx(1000));
  CHECK(o.depth.cols == 640);
  CHECK(o.depth.rows == 480);
  CHECK(o.depth_intrinsics.fx == Approx(572.88277));
  CHECK(o.depth_intrinsics.fy == Approx(542.73998));
  CHECK(o.depth_intrinsics.cx == Approx(314.64917));
  CHECK(o.depth_intrinsics.cy == Approx(240.16046));
  CHECK(o.depth_intrinsics.distortion[0] == Approx(-4.747169e-03));
  CHECK(o.color_intrinsics.fx == Approx(521.17923));
  CHECK(o.color_intrinsics.cx == Approx(322.51599));
  REQUIRE_FALSE(o.color.empty());
  CHECK(o.color.cols == 640);
  // In optical frames: the colour camera sits 1.5 mm to the depth camera's left (MRPT -y is optical
  // +x... and 0.6 mm up) with the same orientation, so T_color_depth is that small translation.
  CHECK(o.T_color_depth.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-6));
  CHECK(o.T_color_depth.translation().norm() == Approx(std::hypot(0.0015, 0.0006)).margin(1e-4));
  // The sensor looks along the robot's x axis: its optical z is the robot's x.
  CHECK((o.T_robot_sensor.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-9));
  const int with_depth = cv::countNonZero(o.depth);
  CHECK(with_depth > 640 * 480 / 2);
}
