#pragma once
// The `report` stage: one HTML page and its pictures, for a person to see in ten seconds whether the
// labels are right: the trajectory from above, the scene preview (when a reconstruct stage is
// upstream), a contact sheet of overlays, per-class pixel and frame counts, the flagged
// observations, and (registered poses) each observation's consistency with the scene.
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "olt/core/fs.h"
#include "olt/model/recording.h"

namespace olt {

struct ReportConfig {
  int contact_sheet_frames = 24;  ///< overlays on the contact sheet, evenly spread over the recording
  int tile_width_px = 240;        ///< width of one overlay on the sheet
};

struct ReportInputs {
  fs::path job_file;  ///< named in the title
  Recording recording;
  std::vector<ObservationPose> poses;  ///< one per observation, in order
  nlohmann::json labels_summary;       ///< the propagate stage's summary
  /// The overlays propagate wrote ("sensor observation", file), in the recording's order.
  std::vector<std::pair<std::string, fs::path>> overlays;
  bool scene_preview = false;  ///< a reconstruct stage upstream made one
};

struct ReportResult {
  std::string html;                          ///< index.html
  std::vector<std::string> pictures;         ///< the page's pictures, in its order
  std::map<std::string, std::string> drawn;  ///< the pictures drawn here, by name (others: the scene preview)
};

ReportResult run_report(const ReportInputs& in, const ReportConfig& c);

}  // namespace olt
