#pragma once
// The typed data that flows between stages, and its JSON form inside cache artifacts.
#include <istream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "olt/core/camera.h"
#include "olt/core/fs.h"
#include "olt/core/geometry.h"
#include "olt/core/hash.h"
#include "olt/core/pieces.h"
#include "olt/model/pose_quality.h"

namespace olt {

/// An image read in place: `path` is absolute, or relative to the source artifact's folder for
/// images a source generated itself (synthetic).
struct ImageFile {
  std::string path;  ///< as the recording's JSON has it
  Digest sha256;     ///< 32 bytes, not 64 hex characters: a recording of 10,000 observations holds 20,000
  /// The folder a relative path is in, where a stage read the recording (shared_recording): one for
  /// all its images (each path made absolute, 10,000 observations' took 2.5 MB). None: as it is.
  std::shared_ptr<const fs::path> folder = nullptr;

  /// The image's file, to read it or name it.
  std::string file() const { return folder ? (*folder / path).string() : path; }
};

struct Observation {
  std::string id;        ///< unique within the recording (e.g. the depth file's stem)
  std::string sensor;    ///< sensor id
  double timestamp = 0;  ///< of the depth image, seconds
  ImageFile depth;
  std::optional<ImageFile> color;
  double color_dt_s = 0;  ///< the colour image's timestamp minus the depth image's, seconds
};

/// Per-sensor calibration, as set by the calibrate stage.
struct SensorCalibration {
  Intrinsics depth;
  Intrinsics color;
  double depth_scale = 1000;  ///< depth image units per metre (5000 for TUM)
  double min_depth_m = 0.1;   ///< nearer depth readings are ignored, metres
  double max_depth_m = 10;    ///< farther depth readings are ignored, metres
  double time_offset_s =
      0;  ///< added to the sensor's timestamps to get the pose source's time (capture latency), seconds
  Pose T_robot_sensor = Pose::Identity();  ///< the sensor's pose on the robot
  Pose T_color_depth = Pose::Identity();   ///< depth camera frame -> colour camera frame
};

struct SensorInfo {
  std::string id;
  int depth_width = 0, depth_height = 0;         ///< pixels
  int color_width = 0, color_height = 0;         ///< pixels; 0 when the sensor has no colour images
  std::optional<SensorCalibration> calibration;  ///< when the recording itself knows it
};

struct Recording {
  std::vector<SensorInfo> sensors;
  std::vector<Observation> observations;     ///< sorted by timestamp, then sensor
  std::string groundtruth;                   ///< TUM trajectory file carried by the source ("" = none)
  std::string groundtruth_frame = "sensor";  ///< whose pose it gives: sensor (the RGB-D camera's) | robot
  std::string boxes;                         ///< native annotation file carried by the source ("" = none)
  std::string laser_scans;                   ///< 2D laser scans, plain text (formats/laser_text.h) ("" = none)
  std::string odometry;                      ///< wheel odometry, plain text (formats/laser_text.h) ("" = none)
  std::string root;  ///< the recording's folder, to name images relative to it ("" = the source artifact)

  const SensorInfo& sensor(const std::string& id) const;
};

using Calibration = std::map<std::string, SensorCalibration>;  ///< by sensor id

/// The pose of one observation, with what the pose source says about its quality.
struct ObservationPose {
  std::string observation;  ///< observation id
  std::string sensor;
  double timestamp = 0;
  Pose T_world_sensor = Pose::Identity();
  bool valid = false;
  std::string flag;     ///< why not valid ("" when valid)
  PoseQuality quality;  ///< what the pose source measured (registration: fitness, inliers, ...)
};

nlohmann::json to_json(const Recording& r);
/// to_json(r).dump(1), made an observation at a time and handed to `sink` about a megabyte at a time
/// (the tree of 100,000 observations took 150 MB).
void recording_text(const Recording& r, const PieceSink& sink);
Recording recording_from_json(const nlohmann::json& j);
/// recording_from_json of a recording's text, each observation taken as it is parsed (never a
/// tree of 10,000 of them); throws nlohmann::json's exceptions as parse and recording_from_json do.
Recording recording_from_text(std::istream& text);
nlohmann::json to_json(const Intrinsics& c);
Intrinsics intrinsics_from_json(const nlohmann::json& j);
nlohmann::json to_json(const SensorCalibration& c);
SensorCalibration calibration_from_json(const nlohmann::json& j);
nlohmann::json to_json(const std::vector<ObservationPose>& poses);
/// to_json(poses).dump(1), made a pose at a time and handed to `sink` about a megabyte at a time.
void poses_text(const std::vector<ObservationPose>& poses, const PieceSink& sink);
std::vector<ObservationPose> poses_from_json(const nlohmann::json& j);
/// poses_from_json of the poses' text, each pose taken as it is parsed.
std::vector<ObservationPose> poses_from_text(std::istream& text);

}  // namespace olt
