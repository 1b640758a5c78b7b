#pragma once
// The `report` stage: one HTML page and its pictures, for a person to see in ten seconds whether the
// labels are right: the trajectory from above, (when a reconstruct stage is upstream) the levelled
// scene with every box drawn and a picture around each box, a contact sheet of overlays, per-class
// pixel and frame counts, the flagged observations, and (registered poses) each observation's
// consistency with the scene.
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/fs.h"
#include "olt/core/memo.h"
#include "olt/formats/scene_points.h"
#include "olt/model/artifact.h"
#include "olt/model/recording.h"
#include "olt/propagate/label_map.h"
#include "olt/reconstruct/preview.h"

namespace olt {

struct ReportConfig {
  int contact_sheet_frames = 24;  ///< overlays on the contact sheet, evenly spread over the recording
  int tile_width_px = 240;        ///< width of one overlay on the sheet
  int worst_frames = 6;           ///< frames listed with the lowest labeled share against their neighbours
  int scene_picture_px = 520;     ///< height of the scene with its boxes (top and front view side by side)
  int box_picture_px = 300;       ///< height of each box's picture
};

/// The reconstruct stage's scene, in the annotation frame.
struct ReportScene {
  /// The points, read and decoded on the first call from any thread (a picture the cache does not
  /// hold is drawn; throws InputError naming the file where it is not a scene's points): once per
  /// digest in `olt watch` (kept between edits), not at all in a run whose pictures all come from
  /// the cache (1.2 M points take 0.02 s in huge pages, 0.2 s on a virtual machine without).
  std::function<std::shared_ptr<const ScenePoints>()> points;
  float voxel_size_m = 0;                      ///< how wide a point is drawn (the file's header)
  std::string points_digest;                   ///< SHA-256 of the points' file: what the pictures are drawn from
  Pose T_world_annotation = Pose::Identity();  ///< annotation frame -> the boxes' (world) frame
  /// Those points ordered by x, made on the first call and kept with them, where the process keeps
  /// memory (`olt watch`: a moved box's picture then looks at the points near it, not at all of
  /// them); empty elsewhere (one picture drawn costs less than the sort).
  std::function<std::shared_ptr<const PointsByX>()> points_by_x;
};

/// One observation as the report shows it: its labels' share and its pose's quality.
struct ReportFrame {
  /// The recording's observation (ReportInputs::recording), and its pose where the poses hold one
  /// (::poses): their names, not copies (10,000 frames' took 1 MB).
  const Observation* observation = nullptr;
  const ObservationPose* pose = nullptr;
  bool labeled = false;        ///< propagate labeled it (false: its pose was flagged and it was skipped)
  int64_t labeled_pixels = 0;  ///< depth pixels inside a box
  int64_t depth_pixels = 0;    ///< pixels with depth
  bool pose_valid = true;
  std::optional<double> consistency;  ///< the pose's consistency with the scene (registration), 0..1
  /// The overlay image propagate wrote: its place in the labels' file list (ReportInputs::labels);
  /// none when it wrote none. Its path, digest and link are made when a tile or a point needs them
  /// (held for 10,000 frames they were 5 MB).
  std::optional<size_t> overlay;

  double labeled_fraction() const { return depth_pixels ? double(labeled_pixels) / double(depth_pixels) : 0.0; }
  /// "SENSOR OBSERVATION", to name it on the page.
  std::string name() const { return observation->sensor + " " + observation->id; }
  /// Why its pose was flagged ("" when it was not).
  std::string flag() const { return pose ? pose->flag : std::string(); }
};

struct ReportInputs {
  fs::path job_file;  ///< named in the title
  /// The recording and its poses (one per observation, in order), shared with the run's other stages.
  std::shared_ptr<const Recording> recording;
  std::shared_ptr<const std::vector<ObservationPose>> poses;
  nlohmann::json labels_summary;    ///< the propagate stage's summary
  std::vector<ReportFrame> frames;  ///< one per observation, in the recording's order
  /// The propagate stage's artifact, where the frames' overlays are (set whenever a frame has one;
  /// the run's, alive while the report is made), and the folder it is published in relative to the
  /// report's page ("../LABELS_ID/").
  const Artifact* labels = nullptr;
  std::string labels_folder;
  std::optional<ReportScene> scene;  ///< a reconstruct stage upstream made one
  std::vector<Box> boxes;            ///< world frame, as the annotations stage wrote them
  LabelMap label_map;                ///< the classes' colours
  /// Reads an overlay's bytes when its tile is drawn (only the frames the page shows are read, not
  /// every frame's overlay held at once); the file system unless a caller says otherwise.
  std::function<std::string(const fs::path&)> read = read_file;
  /// The pictures' and tiles' bytes by what they are drawn from (StageContext::memo: the cache, so an
  /// edit redraws only the pictures it changes); made every time unless a caller says otherwise.
  Memo memo = make_every_time;
};

struct ReportResult {
  std::string html;                                           ///< index.html
  std::vector<std::pair<std::string, std::string>> pictures;  ///< the page's pictures (file, bytes), in its order
};

ReportResult run_report(const ReportInputs& in, const ReportConfig& c);

/// The frame's published overlay relative to the report's page; "" when it has none.
std::string overlay_link(const ReportInputs& in, const ReportFrame& f);

}  // namespace olt
