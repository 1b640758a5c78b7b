#include "olt/model/recording.h"

#include <functional>
#include <stdexcept>

#include "olt/core/json_text.h"
#include "olt/core/pieces.h"

namespace olt {

using nlohmann::json;

const SensorInfo& Recording::sensor(const std::string& id) const {
  for (const auto& s : sensors)
    if (s.id == id) return s;
  throw std::out_of_range("unknown sensor '" + id + "'");
}

namespace {

json image_json(const ImageFile& f) { return {{"path", f.path}, {"sha256", f.sha256.hex()}}; }
ImageFile image_from(const json& j) { return {j.at("path"), Digest(j.at("sha256").get<std::string>())}; }

Observation observation_from(const json& o) {
  Observation obs;
  obs.id = o.at("id");
  obs.sensor = o.at("sensor");
  obs.timestamp = o.at("timestamp");
  obs.depth = image_from(o.at("depth"));
  if (o.contains("color")) obs.color = image_from(o.at("color"));
  obs.color_dt_s = o.value("color_dt_s", 0.0);
  return obs;
}

ObservationPose pose_from(const json& p) {
  ObservationPose pose;
  pose.observation = p.at("observation");
  pose.sensor = p.at("sensor");
  pose.timestamp = p.at("timestamp");
  pose.T_world_sensor = pose_from_json(p.at("T_world_sensor"));
  pose.valid = p.at("valid");
  pose.flag = p.at("flag");
  pose.quality = pose_quality_from_json(p.value("quality", nlohmann::json()));
  return pose;
}

// `text` parsed with each element of the list at `depth` (inside the member `member` of the
// document, or the document itself when `member` is empty) handed to `take` as it completes and
// then dropped: 10,000 observations are never a tree at once. Returns the rest of the document.
json parse_taking(std::istream& text, int depth, const std::string& member,
                  const std::function<void(const json&)>& take) {
  std::string at;  // the top-level member being parsed
  return json::parse(text, [&](int d, json::parse_event_t event, json& parsed) {
    if (d == 1 && event == json::parse_event_t::key) at = parsed.get<std::string>();
    if (d == depth && event == json::parse_event_t::object_end && at == member) {
      take(parsed);
      return false;
    }
    return true;
  });
}

}  // namespace

json to_json(const Intrinsics& c) {
  return {{"width", c.width}, {"height", c.height},        {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx},
          {"cy", c.cy},       {"distortion", c.distortion}};
}

Intrinsics intrinsics_from_json(const json& j) {
  Intrinsics c;
  c.width = j.at("width");
  c.height = j.at("height");
  c.fx = j.at("fx");
  c.fy = j.at("fy");
  c.cx = j.at("cx");
  c.cy = j.at("cy");
  c.distortion = j.at("distortion");
  return c;
}

json to_json(const SensorCalibration& c) {
  return {{"depth", to_json(c.depth)},
          {"color", to_json(c.color)},
          {"depth_scale", c.depth_scale},
          {"min_depth_m", c.min_depth_m},
          {"max_depth_m", c.max_depth_m},
          {"time_offset_s", c.time_offset_s},
          {"T_robot_sensor", pose_to_json(c.T_robot_sensor)},
          {"T_color_depth", pose_to_json(c.T_color_depth)}};
}

SensorCalibration calibration_from_json(const json& j) {
  SensorCalibration c;
  c.depth = intrinsics_from_json(j.at("depth"));
  c.color = intrinsics_from_json(j.at("color"));
  c.depth_scale = j.at("depth_scale");
  c.min_depth_m = j.at("min_depth_m");
  c.max_depth_m = j.at("max_depth_m");
  c.time_offset_s = j.value("time_offset_s", 0.0);
  c.T_robot_sensor = pose_from_json(j.at("T_robot_sensor"));
  c.T_color_depth = pose_from_json(j.at("T_color_depth"));
  return c;
}

namespace {

json observation_json(const Observation& o) {
  json j = {{"id", o.id}, {"sensor", o.sensor}, {"timestamp", o.timestamp}, {"depth", image_json(o.depth)}};
  if (o.color) j["color"] = image_json(*o.color);
  if (o.color_dt_s != 0) j["color_dt_s"] = o.color_dt_s;
  return j;
}

// The recording without its observations ("observations": []).
json recording_head_json(const Recording& r) {
  json sensors = json::array();
  for (const auto& s : r.sensors) {
    json j = {
        {"id", s.id}, {"depth_size", {s.depth_width, s.depth_height}}, {"color_size", {s.color_width, s.color_height}}};
    if (s.calibration) j["calibration"] = to_json(*s.calibration);
    sensors.push_back(std::move(j));
  }
  json out = {{"groundtruth", r.groundtruth},
              {"groundtruth_frame", r.groundtruth_frame},
              {"boxes", r.boxes},
              {"laser_scans", r.laser_scans},
              {"odometry", r.odometry},
              {"root", r.root},
              {"observations", json::array()}};
  out["sensors"] = std::move(sensors);
  return out;
}

}  // namespace

json to_json(const Recording& r) {
  json out = recording_head_json(r);
  json& observations = out["observations"];
  for (const auto& o : r.observations) observations.push_back(observation_json(o));
  return out;
}

void recording_text(const Recording& r, const PieceSink& sink) {
  const std::string head = recording_head_json(r).dump(1);
  // The members are sorted; a value's text holds no line break, so this is the member's own line.
  const std::string member = "\n \"observations\": ";
  const size_t at = head.find(member) + member.size();
  Pieces out(sink);
  out.text().assign(head, 0, at);
  append_array(
      out.text(), r.observations.size(), [&](size_t i) { return observation_json(r.observations[i]); }, 1,
      [&](std::string&) { out.next(); });
  out.text() += head.substr(at + 2);  // after its "[]"
  out.flush();
}

Recording recording_from_json(const json& j) {
  Recording r;
  for (const auto& s : j.at("sensors")) {
    SensorInfo info;
    info.id = s.at("id");
    info.depth_width = s.at("depth_size").at(0);
    info.depth_height = s.at("depth_size").at(1);
    info.color_width = s.at("color_size").at(0);
    info.color_height = s.at("color_size").at(1);
    if (s.contains("calibration")) info.calibration = calibration_from_json(s.at("calibration"));
    r.sensors.push_back(info);
  }
  r.observations.reserve(j.at("observations").size());  // 10,000 and more: not grown by doubling
  for (const auto& o : j.at("observations")) r.observations.push_back(observation_from(o));
  r.groundtruth = j.value("groundtruth", "");
  r.root = j.value("root", "");
  r.boxes = j.value("boxes", "");
  r.groundtruth_frame = j.value("groundtruth_frame", "sensor");
  r.laser_scans = j.value("laser_scans", "");
  r.odometry = j.value("odometry", "");
  return r;
}

namespace {

json pose_json(const ObservationPose& p) {
  return {{"observation", p.observation},
          {"sensor", p.sensor},
          {"timestamp", p.timestamp},
          {"T_world_sensor", pose_to_json(p.T_world_sensor)},
          {"valid", p.valid},
          {"flag", p.flag},
          {"quality", to_json(p.quality)}};
}

}  // namespace

json to_json(const std::vector<ObservationPose>& poses) {
  json out = json::array();
  for (const auto& p : poses) out.push_back(pose_json(p));
  return out;
}

void poses_text(const std::vector<ObservationPose>& poses, const PieceSink& sink) {
  Pieces out(sink);
  append_array(
      out.text(), poses.size(), [&](size_t i) { return pose_json(poses[i]); }, 0, [&](std::string&) { out.next(); });
  out.flush();
}

std::vector<ObservationPose> poses_from_json(const json& j) {
  std::vector<ObservationPose> poses;
  poses.reserve(j.size());
  for (const auto& p : j) poses.push_back(pose_from(p));
  return poses;
}

Recording recording_from_text(std::istream& text) {
  std::vector<Observation> observations;
  // What is left holds the list emptied (or none, an error as in the whole document).
  const json rest =
      parse_taking(text, 2, "observations", [&](const json& o) { observations.push_back(observation_from(o)); });
  Recording r = recording_from_json(rest);
  observations.shrink_to_fit();
  r.observations = std::move(observations);
  return r;
}

std::vector<ObservationPose> poses_from_text(std::istream& text) {
  std::vector<ObservationPose> poses;
  const json rest = parse_taking(text, 1, "", [&](const json& p) { poses.push_back(pose_from(p)); });
  if (!rest.is_array()) throw json::type_error::create(302, "poses: expected a list", &rest);
  poses.shrink_to_fit();
  return poses;
}

}  // namespace olt
