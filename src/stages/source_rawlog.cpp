// `source` format rawlog: an MRPT rawlog (libmrpt; src/rawlog/).
#include <algorithm>

#include "olt/core/hash.h"
#include "olt/core/image.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/rawlog.h"
#include "olt/model/recording.h"
#include "source_formats.h"

namespace olt::source {

// An MRPT rawlog: its RGB-D images written as PNGs, its scans and odometry as text, into the artifact.
nlohmann::json run_rawlog(const StageContext& /*ctx*/, ArtifactWriter& out, const SourceConfig& c) {
  Recording r;
  std::vector<LaserScan> scans;
  std::vector<OdometrySample> odometry;
  std::string laser;
  bool laser_chosen = false;
  int other_scans = 0, out_of_order = 0;
  RawlogVisitor visit;
  visit.scan = [&](LaserScan&& scan, const std::string& label) {
    if (!laser_chosen && (c.laser_sensor.empty() || label == c.laser_sensor)) {
      laser = label;
      laser_chosen = true;
    }
    if (!laser_chosen || label != laser) {
      ++other_scans;
      return;
    }
    if (const std::string problem = check_scan(scan); !problem.empty())
      throw InputError(c.path, "scan " + std::to_string(scans.size()) + " of '" + label + "' at " +
                                   std::to_string(scan.timestamp) + ": " + problem);
    if (!scans.empty() && scan.timestamp <= scans.back().timestamp) {
      ++out_of_order;
    } else {
      scan.index = static_cast<int>(scans.size());
      scans.push_back(std::move(scan));
    }
  };
  visit.odometry = [&](const OdometrySample& s) {
    if (!odometry.empty() && s.timestamp <= odometry.back().timestamp)
      ++out_of_order;
    else
      odometry.push_back(s);
  };
  visit.rgbd = [&](RawlogRgbd&& o) {
    const auto known =
        std::find_if(r.sensors.begin(), r.sensors.end(), [&](const auto& s) { return s.id == o.sensor; });
    if (known != r.sensors.end() &&
        (o.depth.cols != known->depth_width || o.depth.rows != known->depth_height ||
         (!o.color.empty() && (o.color.cols != known->color_width || o.color.rows != known->color_height))))
      throw InputError(c.path, "3D scan of '" + o.sensor + "' at " + std::to_string(o.timestamp) +
                                   ": its images are not the size of the sensor's first ones");
    if (known == r.sensors.end()) {
      if (!safe_id(o.sensor)) throw InputError(c.path, "sensor label '" + o.sensor + "' cannot name output folders");
      SensorInfo sensor{o.sensor, o.depth.cols, o.depth.rows, o.color.cols, o.color.rows, SensorCalibration{}};
      sensor.calibration->depth = o.depth_intrinsics;
      sensor.calibration->color = o.color.empty() ? o.depth_intrinsics : o.color_intrinsics;
      sensor.calibration->depth_scale = o.depth_scale;
      sensor.calibration->T_robot_sensor = o.T_robot_sensor;
      sensor.calibration->T_color_depth = o.T_color_depth;
      r.sensors.push_back(sensor);
    }
    char id[32];
    std::snprintf(id, sizeof(id), "%06zu", r.observations.size());
    const std::string depth = std::string("depth/") + id + ".png", depth_png = encode_png(o.depth);
    out.write(depth, depth_png);
    Observation observation{id, o.sensor, o.timestamp, {depth, sha256_hex(depth_png)}, std::nullopt};
    if (!o.color.empty()) {
      const std::string color = std::string("rgb/") + id + ".png", color_png = encode_png(o.color);
      out.write(color, color_png);
      observation.color = ImageFile{color, sha256_hex(color_png)};
    }
    r.observations.push_back(observation);
  };
  read_rawlog(c.path, visit);
  if (!c.laser_sensor.empty() && !laser_chosen)
    throw InputError(c.path, "holds no 2D scan of laser_sensor '" + c.laser_sensor + "'");
  std::stable_sort(r.observations.begin(), r.observations.end(), [](const Observation& a, const Observation& b) {
    return a.timestamp < b.timestamp || (a.timestamp == b.timestamp && a.sensor < b.sensor);
  });
  if (!scans.empty()) {
    out.write("laser/scans.txt", format_laser_scans(scans));
    r.laser_scans = "laser/scans.txt";
  }
  if (!odometry.empty()) {
    out.write("laser/odometry.txt", format_odometry(odometry));
    r.odometry = "laser/odometry.txt";
  }
  if (r.observations.empty() && scans.empty())
    throw InputError(c.path, "holds no RGB-D observations and no 2D laser scans");
  out.write("recording.json", to_json(r).dump(1));
  return {{"observations", r.observations.size()},
          {"laser_scans", scans.size()},
          {"laser_sensor", laser},
          {"other_laser_scans", other_scans},
          {"odometry_samples", odometry.size()},
          {"dropped_out_of_order", out_of_order}};
}

}  // namespace olt::source
