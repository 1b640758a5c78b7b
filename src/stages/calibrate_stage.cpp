// `calibrate` (olt/stages/calibrate.h): presets, the function, and its codec — the recording's
// sensors in; calibration.json out.
#include "olt/core/error.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/calibrate.h"
#include "olt/stages/kinds.h"
#include "olt/stages/typed_stage.h"

namespace olt {
namespace {

struct Preset {
  const char* name;
  std::array<double, 4> fx_fy_cx_cy;
  std::array<double, 5> distortion;
  double depth_scale;
};

// Published TUM RGB-D calibrations of the colour camera; the depth images are registered to it.
const Preset kPresets[] = {
    {"tum_fr1", {517.3, 516.5, 318.6, 255.3}, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}, 5000},
    {"tum_fr2", {520.9, 521.0, 325.1, 249.7}, {0.2312, -0.7849, -0.0033, -0.0001, 0.9172}, 5000},
    {"tum_fr3", {535.4, 539.2, 320.1, 247.6}, {0, 0, 0, 0, 0}, 5000},
    {"tum_ros_default", {525.0, 525.0, 319.5, 239.5}, {0, 0, 0, 0, 0}, 5000},
};

std::shared_ptr<const Params<CalibrateConfig>> params() {
  static auto p = [] {
    auto sensor = std::make_shared<Params<SensorConfig>>();
    std::vector<std::string> presets = {"none"};
    for (const auto& preset : kPresets) presets.push_back(preset.name);
    sensor->choice("preset", &SensorConfig::preset, presets, "published calibration to start from")
        .numbers("depth_intrinsics", &SensorConfig::depth_intrinsics, 4, "fx fy cx cy of the depth camera, pixels")
        .numbers("depth_distortion", &SensorConfig::depth_distortion, 5, "k1 k2 p1 p2 k3 of the depth camera")
        .numbers("color_intrinsics", &SensorConfig::color_intrinsics, 4, "fx fy cx cy of the colour camera, pixels")
        .numbers("color_distortion", &SensorConfig::color_distortion, 5, "k1 k2 p1 p2 k3 of the colour camera")
        .number("depth_scale", &SensorConfig::depth_scale, non_negative(),
                "depth units per metre; 0 = preset or recording")
        .number("min_depth_m", &SensorConfig::min_depth_m, non_negative(), "nearer readings are ignored, metres")
        .number("max_depth_m", &SensorConfig::max_depth_m, positive(), "farther readings are ignored, metres")
        .number("time_offset_s", &SensorConfig::time_offset_s, between(-1, 1),
                "added to depth timestamps to get the pose source time, s")
        .numbers("pose_on_robot", &SensorConfig::pose_on_robot, 6, "x y z (m) yaw pitch roll (deg) on the robot")
        .numbers("color_from_depth", &SensorConfig::color_from_depth, 6,
                 "T_color_depth: x y z (m) yaw pitch roll (deg)");
    auto t = std::make_shared<Params<CalibrateConfig>>();
    t->struct_map("sensors", &CalibrateConfig::sensors, std::shared_ptr<const Params<SensorConfig>>(sensor),
                  "calibration per sensor id");
    return t;
  }();
  return p;
}

void set_intrinsics(Intrinsics& c, const std::vector<double>& k) {
  c.fx = k[0];
  c.fy = k[1];
  c.cx = k[2];
  c.cy = k[3];
}

// The named preset's intrinsics, distortion and depth scale; false where `name` is none.
bool apply_preset(SensorCalibration& cal, const std::string& name) {
  for (const auto& preset : kPresets) {
    if (name != preset.name) continue;
    set_intrinsics(cal.depth, {preset.fx_fy_cx_cy.begin(), preset.fx_fy_cx_cy.end()});
    cal.depth.distortion = preset.distortion;
    cal.color = cal.depth;
    cal.depth_scale = preset.depth_scale;
    return true;
  }
  return false;
}

std::optional<Pose> pose_of(const std::vector<double>& xyz_ypr_deg) {
  if (xyz_ypr_deg.empty()) return std::nullopt;
  std::array<double, 6> v;
  std::copy(xyz_ypr_deg.begin(), xyz_ypr_deg.end(), v.begin());
  return pose_from_xyz_ypr_deg(v);
}

// The job's numbers over what the recording and the preset gave; true where they give intrinsics.
bool apply_numbers(SensorCalibration& cal, const SensorConfig& config) {
  if (!config.depth_intrinsics.empty()) {
    set_intrinsics(cal.depth, config.depth_intrinsics);
    if (config.color_intrinsics.empty()) set_intrinsics(cal.color, config.depth_intrinsics);
  }
  if (!config.depth_distortion.empty()) {
    std::copy(config.depth_distortion.begin(), config.depth_distortion.end(), cal.depth.distortion.begin());
    if (config.color_distortion.empty()) cal.color.distortion = cal.depth.distortion;
  }
  if (!config.color_intrinsics.empty()) set_intrinsics(cal.color, config.color_intrinsics);
  if (!config.color_distortion.empty())
    std::copy(config.color_distortion.begin(), config.color_distortion.end(), cal.color.distortion.begin());
  if (config.depth_scale > 0) cal.depth_scale = config.depth_scale;
  cal.min_depth_m = config.min_depth_m;
  cal.max_depth_m = config.max_depth_m;
  cal.time_offset_s = config.time_offset_s;
  if (const auto pose = pose_of(config.pose_on_robot)) cal.T_robot_sensor = *pose;
  if (const auto pose = pose_of(config.color_from_depth)) cal.T_color_depth = *pose;
  return !config.depth_intrinsics.empty();
}

// One sensor: what the recording knows, then the preset, then the job's numbers.
SensorCalibration calibrate_sensor(const SensorInfo& info, const SensorConfig* config, const std::string& stage) {
  SensorCalibration cal = info.calibration.value_or(SensorCalibration{});
  bool has_intrinsics = info.calibration.has_value() && info.calibration->depth.fx > 0;  // fx 0: unknown
  cal.depth.width = info.depth_width;
  cal.depth.height = info.depth_height;
  if (config) {
    has_intrinsics = apply_preset(cal, config->preset) || has_intrinsics;
    has_intrinsics = apply_numbers(cal, *config) || has_intrinsics;
  }
  cal.color.width = info.color_width ? info.color_width : info.depth_width;
  cal.color.height = info.color_width ? info.color_height : info.depth_height;
  if (!has_intrinsics)
    throw InputError("stage '" + stage + "'",
                     "sensor '" + info.id + "' has no intrinsics: give a preset or depth_intrinsics");
  if (!(cal.depth_scale > 0)) throw InputError("stage '" + stage + "'", "sensor '" + info.id + "' has no depth_scale");
  return cal;
}

}  // namespace

Calibration run_calibrate(const CalibrateInputs& in, const CalibrateConfig& c) {
  Calibration calibration;
  for (const auto& info : in.sensors) {
    auto it = c.sensors.find(info.id);
    calibration[info.id] = calibrate_sensor(info, it == c.sensors.end() ? nullptr : &it->second, in.stage);
  }
  for (const auto& [id, unused] : c.sensors)
    if (!calibration.count(id))
      throw InputError("stage '" + in.stage + "'", "calibrates sensor '" + id + "', which the recording does not have");
  return calibration;
}

namespace {

CalibrateInputs load(const StageContext& context) {
  return {context.stage.id, shared_recording(context.need("source"))->sensors};
}

nlohmann::json save(const Calibration& calibration, const StageContext& context, ArtifactWriter& out) {
  nlohmann::json sensors = nlohmann::json::object();
  for (const auto& [id, cal] : calibration) sensors[id] = to_json(cal);
  out.write("calibration.json", sensors.dump(1));
  out.publish("calibration.json", context.stage.id + "/calibration.json", "calibration");
  return {{"sensors", sensors.size()}};
}

// A TUM recording has one sensor, named by the source's `sensor` parameter, and carries no
// intrinsics: the job must give them.
void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>& upstream, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const CalibrateConfig c = params()->from_json(stage.params);
  auto source = upstream.find("source");
  if (source == upstream.end() || source->second->params.value("format", "") != "tum") return;
  const std::string sensor = source->second->params.value("sensor", "");
  auto it = c.sensors.find(sensor);
  const std::string at = stage.pointer + "/params";
  for (const auto& [id, unused] : c.sensors)
    if (id != sensor)
      errors.push_back(doc.error_at_key(at + "/sensors/" + pointer_escape(id),
                                        "stage '" + stage.id + "' (calibrate): sensor '" + id +
                                            "' is not in the recording (its sensor is '" + sensor + "')"));
  if (it == c.sensors.end() || (it->second.preset == "none" && it->second.depth_intrinsics.empty()))
    errors.push_back(doc.error_at(at, "stage '" + stage.id + "' (calibrate): sensor '" + sensor +
                                          "' needs a preset or depth_intrinsics (a TUM recording has none)"));
}

}  // namespace

StageKind calibrate_kind() {
  StageKind kind = make_stage_kind({"calibrate", params(), {"source"}, {}, check}, 1, nullptr,
                                   typed_stage(params(), load, run_calibrate, save));
  kind.light = true;  // layering a few numbers: `olt plan` runs it aside to look further ahead
  return kind;
}

}  // namespace olt
