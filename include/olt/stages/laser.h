#pragma once
// What the laser stages (laser_map, poses with method laser) share: the recording's scans and
// odometry, the scan-matching parameters, and the JSON of scan poses.
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

/// Scan matching and range parameters, bound through `get` to the config's LaserMapSettings, each
/// key starting with `prefix`.
template <class Config, class Get>
void add_laser_params(Params<Config>& t, Get get, const std::string& prefix = "") {
  auto setting = [get](auto LaserMapSettings::*m) {
    return [ get, m ](Config & c) -> auto& { return get(c).*m; };
  };
  auto matching = [get](auto ScanMatchSettings::*m) {
    return [ get, m ](Config & c) -> auto& { return get(c).matching.*m; };
  };
  t.number((prefix + "min_range_m").c_str(), setting(&LaserMapSettings::min_range_m), non_negative(),
           "nearer laser returns ignored, m")
      .number((prefix + "max_range_m").c_str(), setting(&LaserMapSettings::max_range_m), positive(),
              "farther laser returns ignored, m")
      .number((prefix + "max_correspondence_m").c_str(), matching(&ScanMatchSettings::max_correspondence_m),
              between(0.001, 100), "scan matching: first pass correspondence distance, m")
      .number((prefix + "min_correspondence_m").c_str(), matching(&ScanMatchSettings::min_correspondence_m),
              between(0.001, 100), "scan matching: last pass correspondence distance, m")
      .integer((prefix + "max_iterations").c_str(), matching(&ScanMatchSettings::max_iterations), between(1, 1000),
               "scan matching: iterations per pass")
      .number((prefix + "huber_m").c_str(), matching(&ScanMatchSettings::huber_m), positive(),
              "scan matching: robust threshold, m")
      .number((prefix + "max_rmse_m").c_str(), setting(&LaserMapSettings::max_rmse_m), positive(),
              "a scan match fails above this RMSE, m")
      .number((prefix + "min_inlier_ratio").c_str(), setting(&LaserMapSettings::min_inlier_ratio), between(0, 1),
              "a scan match fails below this inlier fraction");
}

}  // namespace olt
