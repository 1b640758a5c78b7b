#pragma once
// The `export` stage: the labels in the formats training code reads — COCO instances (RLE masks of
// the instance images) and every observation's boxes in its sensor's frame — and the label map as
// YAML.
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/fs.h"
#include "olt/core/pieces.h"
#include "olt/model/recording.h"
#include "olt/propagate/label_map.h"

namespace olt {

struct ExportConfig {
  bool coco = true;          ///< write instances.json
  bool sensor_boxes = true;  ///< write per-observation boxes in the sensor frame
};

struct ExportInputs {
  /// The recording and its poses (one per observation, in order), shared with the run's other stages.
  std::shared_ptr<const Recording> recording;
  std::shared_ptr<const std::vector<ObservationPose>> poses;
  std::vector<Box> boxes;
  LabelMap map;
  /// Per observation, its instances' masks.json; empty where it was not labeled (strings: 10,000
  /// fs::paths with their parsed parts took 9 MB).
  std::vector<std::string> mask_files;
  /// ... and its digest (hex): what `olt watch` keeps a frame's export by; given only where the
  /// process keeps memory (none given, nothing kept).
  std::vector<std::string> mask_digests;
  /// The name `olt watch` keeps the frames' export under (StageContext::kept_name).
  std::string kept_name;
  fs::path image_root;  ///< COCO file names are relative to it
  /// COCO's `olt_image_root`: where image_root is, relative to instances.json's folder; "images"
  /// for a generated recording, whose images the stage publishes there.
  std::string coco_image_root;
  /// Reads a frame's masks file as the frames are exported (10,000 frames' masks are not held at
  /// once); the file system unless a caller says otherwise.
  std::function<std::string(const fs::path&)> read = read_file;
};

/// One observation's boxes in its sensor's frame: which boxes have labeled pixels in it, and where
/// the sensor was (the file's text is made as it is written: 25 MB at 10,000 observations).
struct SensorBoxes {
  std::string sensor, observation;
  double timestamp = 0;
  Pose T_world_sensor = Pose::Identity();
  std::vector<uint32_t> shown;  ///< positions in ExportResult::boxes, in their order
};

struct ExportResult {
  std::string labels_yaml;
  std::vector<Box> boxes;                 ///< the boxes sensor_boxes name by position
  LabelMap map;                           ///< their class and instance ids
  std::vector<SensorBoxes> sensor_boxes;  ///< of the labeled observations, in order
  /// instances.json's text, its parts in order (16 MB at 10,000 observations: its annotations and
  /// images wait on disk beyond a few megabytes each); none when not written.
  std::vector<SpooledText> coco;
  std::vector<std::string> coco_images;  ///< the COCO images' file names, in order
  bool images_in_cache = false;          ///< a generated recording's: the stage publishes them
  int images = 0, annotations = 0;
};

/// An observation's boxes file (`<sensor>/boxes/<observation>.json`): the boxes it shows in its
/// sensor's frame, as JSON.
std::string sensor_boxes_text(const SensorBoxes& frame, const std::vector<Box>& boxes, const LabelMap& map);

ExportResult run_export(const ExportInputs& in, const ExportConfig& c);

}  // namespace olt
