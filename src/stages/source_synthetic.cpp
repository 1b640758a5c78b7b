// `source` format synthetic: the built-in recording with exact truth (src/source/synthetic.cpp),
// its images written into the artifact.
#include "olt/core/hash.h"
#include "olt/core/image.h"
#include "olt/core/parallel.h"
#include "olt/core/progress.h"
#include "olt/formats/annotations.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/model/recording.h"
#include "olt/source/synthetic.h"
#include "source_formats.h"

namespace olt::source {

namespace {

SyntheticConfig synthetic_config(const SourceConfig& c) {
  SyntheticConfig sc;
  sc.frames = c.frames;
  sc.width = c.width;
  sc.height = c.height;
  sc.rate_hz = c.rate_hz;
  sc.cameras = c.cameras;
  sc.seed = static_cast<unsigned>(c.seed);
  sc.color_dt_s = c.color_dt_s;
  sc.tilt_deg = c.tilt_deg;
  return sc;
}

// The recording's sensors, with their exact calibration: the hand-held camera, or the robot's.
std::vector<SensorInfo> synthetic_sensors(const SyntheticScene& scene, const SyntheticConfig& sc,
                                          const std::vector<std::string>& ids) {
  std::vector<SensorInfo> sensors;
  for (size_t k = 0; k < ids.size(); ++k) {
    SensorInfo sensor{ids[k], sc.width, sc.height, sc.width, sc.height, SensorCalibration{}};
    sensor.calibration->depth = scene.camera;
    sensor.calibration->color = scene.camera;
    sensor.calibration->depth_scale = sc.depth_scale;
    sensor.calibration->T_robot_sensor = scene.T_robot_camera[k];
    if (sc.cameras > 0) sensor.calibration->max_depth_m = 8;  // the Kinect-class range; farther is noise
    sensors.push_back(sensor);
  }
  return sensors;
}

// Every frame rendered and written (depth, colour, the exact object ids); returns the camera's truth.
// Frames in parallel, each rendered and encoded by one thread: no thread waits between a frame's
// rendering and its encoding.
Trajectory write_frames(const SyntheticScene& scene, const std::vector<std::string>& ids, Recording& r,
                        ArtifactWriter& out) {
  const size_t n = scene.timestamps.size();
  std::vector<Observation> observations(n);
  Progress rendered("observations rendered", n);
  parallel_for(n, [&](size_t i) {
    rendered.advance();
    const SyntheticFrame frame = render_synthetic_frame(scene, i);
    char id[32];
    std::snprintf(id, sizeof(id), "%06zu", i);
    const std::string depth = std::string("depth/") + id + ".png", color = std::string("rgb/") + id + ".png";
    const std::string depth_png = encode_png(frame.depth), color_png = encode_png(frame.color);
    out.write(depth, depth_png);
    out.write(color, color_png);
    out.write(std::string("groundtruth/objects/") + id + ".png", encode_png(frame.object));
    const std::string& sensor = ids[static_cast<size_t>(scene.camera_of[i])];
    observations[i] = {id,
                       sensor,
                       scene.timestamps[i],
                       {depth, Digest(sha256_hex(depth_png))},
                       ImageFile{color, Digest(sha256_hex(color_png))},
                       scene.color_dt_s[i]};
  });
  Trajectory truth;
  const Pose T_truth_room = synthetic_truth_frame(scene.config.tilt_deg);
  for (size_t i = 0; i < n; ++i) {
    r.observations.push_back(std::move(observations[i]));
    truth.push_back({scene.timestamps[i], T_truth_room * scene.T_world_camera[i]});
  }
  return truth;
}

}  // namespace

nlohmann::json run_synthetic(const StageContext& /*ctx*/, ArtifactWriter& out, const SourceConfig& c) {
  const SyntheticConfig sc = synthetic_config(c);
  const SyntheticScene scene = make_synthetic_scene(sc);
  const bool robot = sc.cameras > 0;
  const std::vector<std::string> ids = robot ? scene.sensors : std::vector<std::string>{c.sensor};
  Recording r;
  r.sensors = synthetic_sensors(scene, sc, ids);
  Trajectory truth = write_frames(scene, ids, r, out);
  if (robot) {  // the truth is the robot's; each camera's follows from its pose on the robot
    truth = scene.robot_truth;
    r.groundtruth_frame = "robot";
    out.write("laser/scans.txt", format_laser_scans(scene.scans));
    out.write("laser/odometry.txt", format_odometry(scene.odometry));
    r.laser_scans = "laser/scans.txt";
    r.odometry = "laser/odometry.txt";
  }
  out.write("groundtruth/trajectory.txt", format_tum_trajectory(truth));
  std::vector<Box> boxes = scene.annotations;
  for (auto& b : boxes) b.T_world_box = synthetic_truth_frame(sc.tilt_deg) * b.T_world_box;
  out.write("groundtruth/boxes.json", format_native_annotations(boxes));
  r.groundtruth = "groundtruth/trajectory.txt";
  r.boxes = "groundtruth/boxes.json";
  write_recording(out, r);
  nlohmann::json summary = {{"observations", r.observations.size()}};
  if (robot) {
    summary["laser_scans"] = scene.scans.size();
    summary["odometry_samples"] = scene.odometry.size();
  }
  return summary;
}

}  // namespace olt::source
