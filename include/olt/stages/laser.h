#pragma once
// What the laser stages (laser_map, poses with method laser) share: the recording's scans and
// odometry, the scan-matching parameters, and the JSON of scan poses.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/config/params.h"
#include "olt/laser/laser_map.h"
#include "olt/model/recording.h"

namespace olt {

struct LaserData {
  std::vector<LaserScan> scans;
  std::vector<OdometrySample> odometry;  ///< empty when the recording has none (then: constant pose guess)
};

/// Throws InputError naming the stage when the recording has no laser scans.
LaserData load_laser_data(const Recording& recording, const std::string& stage);

nlohmann::json to_json(const std::vector<ScanPose>& poses);
std::vector<ScanPose> scan_poses_from_json(const nlohmann::json& j);

/// What is inconsistent between laser settings ("" when nothing), e.g. a first pass nearer than
/// the last.
std::string laser_settings_problem(const LaserMapSettings& s);

/// The settings localizing scans in a map (poses, method laser): ranges, scan matching (nested:
/// matching.huber_m, ...) and when a match fails.
std::shared_ptr<const Params<LaserMapSettings>> laser_localization_params();
/// Those and the mapping's own: keyframes and loop closures (laser_map).
std::shared_ptr<const Params<LaserMapSettings>> laser_mapping_params();

}  // namespace olt
