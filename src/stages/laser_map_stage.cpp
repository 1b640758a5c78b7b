// `laser_map`: the 2D map of the recording's laser scans (paper Sec. III-B), with the robot's pose
// at every scan. Publishes the map (points with normals), the robot trajectory (TUM) and a picture.
#include <cstdio>

#include "olt/core/error.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/laser/laser_map.h"
#include "olt/laser/map_image.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
#include "olt/stages/laser.h"
#include "olt/stages/laser_map.h"
#include "olt/stages/typed_stage.h"

namespace olt {
namespace {

std::shared_ptr<const Params<LaserMapConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<LaserMapConfig>>();
    t->embed(&LaserMapConfig::settings, *laser_mapping_params())
        .number("image_resolution_m", &LaserMapConfig::image_resolution_m, between(0.001, 10),
                "map.png metres per pixel")
        .integer("image_max_px", &LaserMapConfig::image_max_px, between(64, 20000), "map.png longer side at most, px")
        .renamed_flat("", "matching");
    return t;
  }();
  return p;
}

}  // namespace

LaserMapResult run_laser_map(const LaserData& in, const LaserMapConfig& c) {
  LaserMapResult result{build_laser_map(in.scans, in.odometry, c.settings), {}};
  result.picture_png = render_map_png(result.map.map.points(), result.map.poses, c.image_resolution_m, c.image_max_px);
  return result;
}

namespace {

LaserData load(const StageContext& context) {
  return load_laser_data(*shared_recording(context.need("source")), context.stage.id);
}

nlohmann::json save(const LaserMapResult& result, const StageContext& context, ArtifactWriter& out) {
  const LaserMap& map = result.map;
  out.write("map.txt", format_point_map(map.map.points(), map.map.normals()));
  Trajectory robot;
  for (const auto& p : map.poses) robot.push_back({p.timestamp, to_pose3(p.T_map_robot)});
  out.write("robot_trajectory.txt", format_tum_trajectory(robot));
  out.write("scan_poses.json", to_json(map.poses).dump(1));
  out.write("map.png", result.picture_png);
  for (const auto& [file, kind] : {std::pair{"map.txt", "laser_map"},
                                   {"robot_trajectory.txt", "robot_trajectory"},
                                   {"map.png", "laser_map_image"}})
    out.publish(file, context.stage.id + "/" + file, kind);

  int keyframes = 0;
  double length = 0;
  nlohmann::json flagged = nlohmann::json::array();
  for (size_t i = 0; i < map.poses.size(); ++i) {
    keyframes += map.poses[i].key;
    if (i > 0) length += (map.poses[i].T_map_robot.translation() - map.poses[i - 1].T_map_robot.translation()).norm();
    if (!map.poses[i].valid) flagged.push_back({{"scan", i}, {"flag", map.poses[i].flag}});
  }
  return {{"scans", map.poses.size()},    {"keyframes", keyframes},  {"loop_closures", map.loop_closures},
          {"map_points", map.map.size()}, {"path_length_m", length}, {"flagged", flagged}};
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>&, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const LaserMapConfig c = params()->from_json(stage.params);
  if (const std::string problem = laser_settings_problem(c.settings); !problem.empty())
    errors.push_back(doc.error_at(stage.pointer + "/params", "stage '" + stage.id + "' (laser_map): " + problem));
}

}  // namespace

StageKind laser_map_kind() {
  return make_stage_kind({"laser_map", params(), {"source"}, {}, check}, 2, nullptr,
                         typed_stage(params(), load, run_laser_map, save));
}

}  // namespace olt
