// `source` format rawlog: an MRPT rawlog (libmrpt; src/rawlog/).
#include <algorithm>

#include "olt/core/hash.h"
#include "olt/core/image.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/rawlog.h"
#include "olt/model/recording.h"
#include "source_formats.h"

namespace olt::source {

namespace {

// What a rawlog holds, gathered as the reader visits it: the RGB-D observations (images written into
// the artifact as they come), the chosen laser's scans, the odometry.
class RawlogGather {
 public:
  RawlogGather(const SourceConfig& c, ArtifactWriter& out) : c_(c), out_(out) {}

  RawlogVisitor visitor() {
    RawlogVisitor visit;
    visit.scan = [this](LaserScan&& scan, const std::string& label) { on_scan(std::move(scan), label); };
    visit.odometry = [this](const OdometrySample& s) {
      if (!odometry_.empty() && s.timestamp <= odometry_.back().timestamp)
        ++out_of_order_;
      else
        odometry_.push_back(s);
    };
    visit.rgbd = [this](RawlogRgbd&& o) { on_rgbd(std::move(o)); };
    return visit;
  }

  nlohmann::json finish() {
    if (!c_.laser_sensor.empty() && !laser_chosen_)
      throw InputError(c_.path, "holds no 2D scan of laser_sensor '" + c_.laser_sensor + "'");
    sort_by_time(r_.observations);
    if (!scans_.empty()) {
      out_.write("laser/scans.txt", format_laser_scans(scans_));
      r_.laser_scans = "laser/scans.txt";
    }
    if (!odometry_.empty()) {
      out_.write("laser/odometry.txt", format_odometry(odometry_));
      r_.odometry = "laser/odometry.txt";
    }
    if (r_.observations.empty() && scans_.empty())
      throw InputError(c_.path, "holds no RGB-D observations and no 2D laser scans");
    write_recording(out_, r_);
    return {{"observations", r_.observations.size()},
            {"laser_scans", scans_.size()},
            {"laser_sensor", laser_},
            {"other_laser_scans", other_scans_},
            {"odometry_samples", odometry_.size()},
            {"dropped_out_of_order", out_of_order_}};
  }

 private:
  // Scans of the laser chosen (laser_sensor, else the first seen), in time order.
  void on_scan(LaserScan&& scan, const std::string& label) {
    if (!laser_chosen_ && (c_.laser_sensor.empty() || label == c_.laser_sensor)) {
      laser_ = label;
      laser_chosen_ = true;
    }
    if (!laser_chosen_ || label != laser_) {
      ++other_scans_;
      return;
    }
    if (const std::string problem = check_scan(scan); !problem.empty())
      throw InputError(c_.path, "scan " + std::to_string(scans_.size()) + " of '" + label + "' at " +
                                    std::to_string(scan.timestamp) + ": " + problem);
    if (!scans_.empty() && scan.timestamp <= scans_.back().timestamp) {
      ++out_of_order_;
      return;
    }
    scan.index = static_cast<int>(scans_.size());
    scans_.push_back(std::move(scan));
  }

  void on_rgbd(RawlogRgbd&& o) {
    add_sensor(o);
    char id[32];
    std::snprintf(id, sizeof(id), "%06zu", r_.observations.size());
    const std::string depth = std::string("depth/") + id + ".png", depth_png = encode_png(o.depth);
    out_.write(depth, depth_png);
    Observation observation{id, o.sensor, o.timestamp, {depth, Digest(sha256_hex(depth_png))}, std::nullopt};
    if (!o.color.empty()) {
      const std::string color = std::string("rgb/") + id + ".png", color_png = encode_png(o.color);
      out_.write(color, color_png);
      observation.color = ImageFile{color, Digest(sha256_hex(color_png))};
    }
    r_.observations.push_back(observation);
  }

  // The observation's sensor, from its first observation (whose images set its sizes).
  void add_sensor(const RawlogRgbd& o) {
    const auto known =
        std::find_if(r_.sensors.begin(), r_.sensors.end(), [&](const auto& s) { return s.id == o.sensor; });
    if (known != r_.sensors.end()) {
      if (o.depth.cols != known->depth_width || o.depth.rows != known->depth_height ||
          (!o.color.empty() && (o.color.cols != known->color_width || o.color.rows != known->color_height)))
        throw InputError(c_.path, "3D scan of '" + o.sensor + "' at " + std::to_string(o.timestamp) +
                                      ": its images are not the size of the sensor's first ones");
      return;
    }
    if (!safe_id(o.sensor)) throw InputError(c_.path, "sensor label '" + o.sensor + "' cannot name output folders");
    SensorInfo sensor{o.sensor, o.depth.cols, o.depth.rows, o.color.cols, o.color.rows, SensorCalibration{}};
    sensor.calibration->depth = o.depth_intrinsics;
    sensor.calibration->color = o.color.empty() ? o.depth_intrinsics : o.color_intrinsics;
    sensor.calibration->depth_scale = o.depth_scale;
    sensor.calibration->T_robot_sensor = o.T_robot_sensor;
    sensor.calibration->T_color_depth = o.T_color_depth;
    r_.sensors.push_back(sensor);
  }

  const SourceConfig& c_;
  ArtifactWriter& out_;
  Recording r_;
  std::vector<LaserScan> scans_;
  std::vector<OdometrySample> odometry_;
  std::string laser_;
  bool laser_chosen_ = false;
  int other_scans_ = 0, out_of_order_ = 0;
};

}  // namespace

// An MRPT rawlog: its RGB-D images written as PNGs, its scans and odometry as text, into the artifact.
nlohmann::json run_rawlog(const StageContext& /*ctx*/, ArtifactWriter& out, const SourceConfig& c) {
  RawlogGather gather(c, out);
  read_rawlog(c.path, gather.visitor());
  return gather.finish();
}

}  // namespace olt::source
