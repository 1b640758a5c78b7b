#pragma once
// The `export` stage: the labels in the formats training code reads — COCO instances (RLE masks of
// the instance images) and every observation's boxes in its sensor's frame — and the label map as
// YAML.
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "olt/core/pieces.h"
#include "olt/model/recording.h"
#include "olt/propagate/label_map.h"

namespace olt {

struct ExportConfig {
  bool coco = true;          ///< write instances.json
  bool sensor_boxes = true;  ///< write per-observation boxes in the sensor frame
};

/// A frame's masks file (olt/propagate/frame_masks.h).
struct MasksFile {
  std::string path;
  Digest sha256;
};

struct ExportInputs {
  /// The recording and its poses (one per observation, in order), shared with the run's other stages.
  std::shared_ptr<const Recording> recording;
  std::shared_ptr<const std::vector<ObservationPose>> poses;
  std::vector<Box> boxes;
  LabelMap map;
  /// Each observation's instances' masks file, by its place: where it is, and its digest (what
  /// `olt watch` keeps a frame's export by; none: nothing kept); none where it was not labeled (its
  /// pose flagged). Looked up as the frames are exported: 10,000 paths held took 1.7 MB.
  std::function<std::optional<MasksFile>(size_t)> masks_file;
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

/// One observation's boxes in its sensor's frame: which boxes have labeled pixels in it (the file's
/// text is made as it is written: 25 MB at 10,000 observations; the observation's names and pose are
/// the recording's: copied, 10,000 took 2.2 MB).
struct SensorBoxes {
  uint32_t observation = 0;     ///< its place in ExportResult::recording and ::poses
  std::vector<uint32_t> shown;  ///< positions in ExportResult::boxes, in their order
};

struct ExportResult {
  /// The recording and its poses, as ExportInputs has them: where sensor_boxes' observations are.
  std::shared_ptr<const Recording> recording;
  std::shared_ptr<const std::vector<ObservationPose>> poses;
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
std::string sensor_boxes_text(const ExportResult& result, const SensorBoxes& frame);

ExportResult run_export(const ExportInputs& in, const ExportConfig& c);

}  // namespace olt
