#pragma once
// The `report` stage: one HTML page and its pictures, for a person to see in ten seconds whether the
// labels are right: the trajectory from above, (when a reconstruct stage is upstream) the levelled
// scene with every box drawn and a picture around each box, a contact sheet of overlays, per-class
// pixel and frame counts, the flagged observations, and (registered poses) each observation's
// consistency with the scene.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/fs.h"
#include "olt/formats/scene_points.h"
#include "olt/model/recording.h"
#include "olt/propagate/label_map.h"

namespace olt {

struct ReportConfig {
  int contact_sheet_frames = 24;  ///< overlays on the contact sheet, evenly spread over the recording
  int tile_width_px = 240;        ///< width of one overlay on the sheet
  int scene_picture_px = 520;     ///< height of the scene with its boxes (top and front view side by side)
  int box_picture_px = 300;       ///< height of each box's picture
};

/// The reconstruct stage's scene, in the annotation frame.
struct ReportScene {
  ScenePoints points;
  Pose T_world_annotation = Pose::Identity();  ///< annotation frame -> the boxes' (world) frame
};

struct ReportInputs {
  fs::path job_file;  ///< named in the title
  Recording recording;
  std::vector<ObservationPose> poses;  ///< one per observation, in order
  nlohmann::json labels_summary;       ///< the propagate stage's summary
  /// The overlays propagate wrote ("sensor observation", file), in the recording's order.
  std::vector<std::pair<std::string, fs::path>> overlays;
  std::optional<ReportScene> scene;  ///< a reconstruct stage upstream made one
  std::vector<Box> boxes;            ///< world frame, as the annotations stage wrote them
  LabelMap label_map;                ///< the classes' colours
};

struct ReportResult {
  std::string html;                                           ///< index.html
  std::vector<std::pair<std::string, std::string>> pictures;  ///< the page's pictures (file, bytes), in its order
};

ReportResult run_report(const ReportInputs& in, const ReportConfig& c);

}  // namespace olt
