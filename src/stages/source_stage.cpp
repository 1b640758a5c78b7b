// `source`: reads a recording into an index of observations (images stay where they are and are
// identified by content hash), or generates the built-in synthetic recording.

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <set>

#include "olt/core/error.h"
#include "olt/core/hash.h"
#include "olt/core/image.h"
#include "olt/formats/annotations.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/plain_text_layout.h"
#include "olt/formats/rawlog.h"
#include "olt/formats/tum.h"
#include "olt/model/recording.h"
#include "olt/source/associate.h"
#include "olt/source/synthetic.h"
#include "olt/stages/kinds.h"

namespace olt {
namespace {

struct SourceConfig {
  std::string format = "tum";    ///< tum | synthetic | laser_text | rawlog | plain_text
  std::string path;              ///< tum: the dataset folder holding rgb.txt and depth.txt; rawlog: the file;
                                 ///< plain_text: the sequence file
  std::string observations;      ///< plain_text: the folder of the observation files (default: the sequence
                                 ///< file's path without its extension)
  std::string laser_sensor;      ///< rawlog: the laser whose scans are used (sensorLabel; default: the first)
  std::string scans;             ///< laser_text: the scans file
  std::string odometry;          ///< laser_text: the odometry file (optional)
  std::string sensor = "rgbd";   ///< id given to the recording's RGB-D camera
  double max_color_dt_s = 0.02;  ///< tum: largest depth-colour time difference of a pair, seconds
  int frames = 30;               ///< synthetic: number of observations
  int width = 640;               ///< synthetic: image width, pixels
  int height = 480;              ///< synthetic: image height, pixels
  double rate_hz = 10;           ///< synthetic: observations per second (per camera)
  int cameras = 0;               ///< synthetic: 0 = hand-held camera; 1..4 = a robot with a laser and this many cameras
  int seed = 1;                  ///< synthetic robot: noise and odometry drift
};

std::shared_ptr<const Params<SourceConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<SourceConfig>>();
    t->choice("format", &SourceConfig::format, {"tum", "synthetic", "laser_text", "rawlog", "plain_text"},
              "recording layout")
        .path("path", &SourceConfig::path, true,
              "tum: dataset folder with rgb.txt and depth.txt; rawlog: the file; plain_text: the sequence file")
        .path("observations", &SourceConfig::observations, true,
              "plain_text: folder of <id>_depth.png, ... (default: the sequence file without extension)")
        .text("laser_sensor", &SourceConfig::laser_sensor,
              "rawlog, plain_text: sensor label of the laser to use (default: the first)")
        .path("scans", &SourceConfig::scans, true, "laser_text: 2D laser scans, one per line")
        .path("odometry", &SourceConfig::odometry, true, "laser_text: odometry, one pose per line")
        .text("sensor", &SourceConfig::sensor, "sensor id of the RGB-D camera")
        .number("max_color_dt_s", &SourceConfig::max_color_dt_s, non_negative(),
                "tum: largest depth-colour time difference of a pair, seconds")
        .integer("frames", &SourceConfig::frames, between(1, 100000), "synthetic: observations")
        .integer("width", &SourceConfig::width, between(16, 4096), "synthetic: image width, pixels")
        .integer("height", &SourceConfig::height, between(16, 4096), "synthetic: image height, pixels")
        .number("rate_hz", &SourceConfig::rate_hz, between(0.1, 1000), "synthetic: observations per second per camera")
        .integer("cameras", &SourceConfig::cameras, between(0, 4),
                 "synthetic: 0 hand-held camera; 1-4 a robot with a 2D laser and this many RGB-D cameras")
        .integer("seed", &SourceConfig::seed, between(0, 2147483647), "synthetic robot: noise and odometry drift");
    return t;
  }();
  return p;
}

// The sensor id names output folders (labels/<sensor>/...): nothing that could leave them.
bool safe_sensor_id(const std::string& id) {
  return !id.empty() && id.size() <= 64 && (std::isalnum(static_cast<unsigned char>(id[0])) || id[0] == '_') &&
         std::all_of(id.begin(), id.end(), [](char ch) {
           return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-';
         });
}

struct TumLists {
  std::vector<TumListEntry> depth, color;
};

TumLists read_tum_lists(const fs::path& dir) {
  const fs::path depth = dir / "depth.txt", color = dir / "rgb.txt";
  return {parse_tum_list(depth.string(), read_file(depth)), parse_tum_list(color.string(), read_file(color))};
}

// The laser_text files, parsed (bad input is found before anything runs).
struct LaserText {
  std::vector<LaserScan> scans;
  std::vector<OdometrySample> odometry;
};

LaserText read_laser_text(const SourceConfig& c) {
  LaserText t;
  t.scans = parse_laser_scans(c.scans, read_file(c.scans));
  if (t.scans.empty()) throw InputError(c.scans, "holds no scans");
  if (!c.odometry.empty()) t.odometry = parse_odometry(c.odometry, read_file(c.odometry));
  return t;
}

// The plain-text layout: each entry of the sequence file with its files (bad input is found before
// anything runs, at the sequence file's line).
struct PlainTextObservation {
  PlainTextEntry entry;
  fs::path scan, depth, intensity;  ///< those that exist
};

fs::path plain_text_folder(const SourceConfig& c) {
  if (!c.observations.empty()) return c.observations;
  fs::path folder = c.path;
  return folder.replace_extension();
}

std::vector<PlainTextObservation> read_plain_text(const SourceConfig& c) {
  const fs::path folder = plain_text_folder(c);
  std::vector<PlainTextObservation> out;
  std::set<std::string> ids;
  std::map<std::string, std::pair<PngHeader, std::optional<PngHeader>>> first_images;  // by sensor
  for (const auto& e : parse_plain_text_sequence(c.path, read_file(c.path))) {
    // Ids name the observation's files here and its outputs later: nothing that could leave a folder.
    if (!safe_sensor_id(e.id))
      throw InputError({{c.path, e.line, 1, "observation id '" + e.id + "' must hold only letters, digits, '_', '.' "
                                            "and '-' (it names files)"}});
    if (!ids.insert(e.id).second) throw InputError({{c.path, e.line, 1, "observation id '" + e.id + "' repeats"}});
    PlainTextObservation o{e, folder / (e.id + "_scan.txt"), folder / (e.id + "_depth.png"),
                           folder / (e.id + "_intensity.png")};
    if (!fs::exists(o.scan)) o.scan.clear();
    if (!fs::exists(o.depth)) o.depth.clear();
    if (!fs::exists(o.intensity)) o.intensity.clear();
    if (o.scan.empty() && o.depth.empty())
      throw InputError({{c.path, e.line, 1,
                         "observation " + e.id + ": neither " + (folder / (e.id + "_scan.txt")).string() + " nor " +
                             (folder / (e.id + "_depth.png")).string() + " exists"}});
    if (o.scan.empty()) {  // an RGB-D observation: its images the size of its sensor's first ones
      const PngHeader depth = read_png_header(o.depth);
      if (!depth.grey16())
        throw InputError({{c.path, e.line, 1,
                           o.depth.string() + ": expected a 16-bit single-channel PNG, found " + depth.describe()}});
      std::optional<PngHeader> intensity;
      if (!o.intensity.empty()) intensity = read_png_header(o.intensity);
      const auto [first, inserted] = first_images.emplace(e.sensor, std::make_pair(depth, intensity));
      const auto same = [](const PngHeader& a, const PngHeader& b) { return a.width == b.width && a.height == b.height; };
      if (!inserted && (!same(first->second.first, depth) || intensity.has_value() != first->second.second.has_value() ||
                        (intensity && !same(*first->second.second, *intensity))))
        throw InputError({{c.path, e.line, 1,
                           "observation " + e.id + ": its images are not the size of sensor " + e.sensor +
                               "'s first ones (or it lacks the intensity image they have)"}});
    }
    out.push_back(o);
  }
  return out;
}

std::vector<fs::path> files_read(const StageDecl& stage) {
  const SourceConfig c = params()->from_json(stage.params);
  if (c.format == "plain_text") {
    std::vector<fs::path> files = {c.path};
    for (const auto& o : read_plain_text(c)) {
      for (const fs::path& f : {o.scan, o.depth, o.intensity})
        if (!f.empty()) files.push_back(f);
      if (o.scan.empty()) continue;
      LaserScan scan = parse_plain_text_scan(o.scan.string(), read_file(o.scan), o.entry);  // found before anything runs
      if (const std::string problem = check_scan(scan); !problem.empty())
        throw InputError({{c.path, o.entry.line, 1, "scan " + o.entry.id + ": " + problem}});
    }
    return files;
  }
  if (c.format == "laser_text") {
    read_laser_text(c);
    std::vector<fs::path> files = {c.scans};
    if (!c.odometry.empty()) files.push_back(c.odometry);
    return files;
  }
  if (c.format == "rawlog") return {c.path};
  if (c.format != "tum") return {};
  const fs::path dir = c.path;
  const TumLists lists = read_tum_lists(dir);
  std::vector<fs::path> files = {dir / "depth.txt", dir / "rgb.txt"};
  for (const auto& e : lists.depth) files.push_back(resolve_path(dir, e.file));
  for (const auto& e : lists.color) files.push_back(resolve_path(dir, e.file));
  return files;
}

void image_size(const fs::path& file, int* width, int* height) {
  const PngHeader header = read_png_header(file);
  *width = header.width;
  *height = header.height;
}

void run_tum(StageRun& run, const SourceConfig& c) {
  const fs::path dir = c.path;
  const TumLists lists = read_tum_lists(dir);
  if (lists.depth.empty()) throw InputError((dir / "depth.txt").string(), "lists no depth images");
  std::vector<double> depth_times, color_times;
  for (const auto& e : lists.depth) depth_times.push_back(e.timestamp);
  for (const auto& e : lists.color) color_times.push_back(e.timestamp);
  const auto pairs = associate_nearest(depth_times, color_times, c.max_color_dt_s);

  Recording r;
  SensorInfo sensor;
  sensor.id = c.sensor;
  image_size(resolve_path(dir, lists.depth.front().file), &sensor.depth_width, &sensor.depth_height);
  int unpaired = 0;
  for (size_t i = 0; i < lists.depth.size(); ++i) {
    const fs::path depth = resolve_path(dir, lists.depth[i].file);
    Observation o;
    o.id = fs::path(lists.depth[i].file).stem().string();
    o.sensor = c.sensor;
    o.timestamp = lists.depth[i].timestamp;
    o.depth = {depth.string(), run.digests.digest(depth)};
    if (pairs[i]) {
      const fs::path color = resolve_path(dir, lists.color[*pairs[i]].file);
      o.color = ImageFile{color.string(), run.digests.digest(color)};
      if (sensor.color_width == 0) image_size(color, &sensor.color_width, &sensor.color_height);
    } else {
      ++unpaired;
    }
    r.observations.push_back(o);
  }
  r.sensors.push_back(sensor);
  r.root = dir.string();
  const fs::path groundtruth = dir / "groundtruth.txt";
  if (fs::exists(groundtruth)) r.groundtruth = groundtruth.string();
  run.write("recording.json", to_json(r).dump(1));
  run.summary = {{"observations", r.observations.size()}, {"without_color", unpaired}};
}

// An MRPT rawlog: its RGB-D images written as PNGs, its scans and odometry as text, into the artifact.
void run_rawlog(StageRun& run, const SourceConfig& c) {
  Recording r;
  std::vector<LaserScan> scans;
  std::vector<OdometrySample> odometry;
  std::string laser;
  bool laser_chosen = false;
  int other_scans = 0, out_of_order = 0;
  RawlogVisitor visit;
  visit.scan = [&](LaserScan&& scan, const std::string& label) {
    if (!laser_chosen && (c.laser_sensor.empty() || label == c.laser_sensor)) {
      laser = label;
      laser_chosen = true;
    }
    if (!laser_chosen || label != laser) {
      ++other_scans;
      return;
    }
    if (const std::string problem = check_scan(scan); !problem.empty())
      throw InputError(c.path, "scan " + std::to_string(scans.size()) + " of '" + label + "' at " +
                                   std::to_string(scan.timestamp) + ": " + problem);
    if (!scans.empty() && scan.timestamp <= scans.back().timestamp) {
      ++out_of_order;
    } else {
      scan.index = static_cast<int>(scans.size());
      scans.push_back(std::move(scan));
    }
  };
  visit.odometry = [&](const OdometrySample& s) {
    if (!odometry.empty() && s.timestamp <= odometry.back().timestamp)
      ++out_of_order;
    else
      odometry.push_back(s);
  };
  visit.rgbd = [&](RawlogRgbd&& o) {
    const auto known = std::find_if(r.sensors.begin(), r.sensors.end(), [&](const auto& s) { return s.id == o.sensor; });
    if (known != r.sensors.end() &&
        (o.depth.cols != known->depth_width || o.depth.rows != known->depth_height ||
         (!o.color.empty() && (o.color.cols != known->color_width || o.color.rows != known->color_height))))
      throw InputError(c.path, "3D scan of '" + o.sensor + "' at " + std::to_string(o.timestamp) +
                                   ": its images are not the size of the sensor's first ones");
    if (known == r.sensors.end()) {
      if (!safe_sensor_id(o.sensor))
        throw InputError(c.path, "sensor label '" + o.sensor + "' cannot name output folders");
      SensorInfo sensor{o.sensor, o.depth.cols, o.depth.rows, o.color.cols, o.color.rows, SensorCalibration{}};
      sensor.calibration->depth = o.depth_intrinsics;
      sensor.calibration->color = o.color.empty() ? o.depth_intrinsics : o.color_intrinsics;
      sensor.calibration->depth_scale = o.depth_scale;
      sensor.calibration->T_robot_sensor = o.T_robot_sensor;
      sensor.calibration->T_color_depth = o.T_color_depth;
      r.sensors.push_back(sensor);
    }
    char id[32];
    std::snprintf(id, sizeof(id), "%06zu", r.observations.size());
    const std::string depth = std::string("depth/") + id + ".png", depth_png = encode_png(o.depth);
    run.write(depth, depth_png);
    Observation observation{id, o.sensor, o.timestamp, {depth, sha256_hex(depth_png)}, std::nullopt};
    if (!o.color.empty()) {
      const std::string color = std::string("rgb/") + id + ".png", color_png = encode_png(o.color);
      run.write(color, color_png);
      observation.color = ImageFile{color, sha256_hex(color_png)};
    }
    r.observations.push_back(observation);
  };
  read_rawlog(c.path, visit);
  if (!c.laser_sensor.empty() && !laser_chosen)
    throw InputError(c.path, "holds no 2D scan of laser_sensor '" + c.laser_sensor + "'");
  std::stable_sort(r.observations.begin(), r.observations.end(), [](const Observation& a, const Observation& b) {
    return a.timestamp < b.timestamp || (a.timestamp == b.timestamp && a.sensor < b.sensor);
  });
  if (!scans.empty()) {
    run.write("laser/scans.txt", format_laser_scans(scans));
    r.laser_scans = "laser/scans.txt";
  }
  if (!odometry.empty()) {
    run.write("laser/odometry.txt", format_odometry(odometry));
    r.odometry = "laser/odometry.txt";
  }
  if (r.observations.empty() && scans.empty())
    throw InputError(c.path, "holds no RGB-D observations and no 2D laser scans");
  run.write("recording.json", to_json(r).dump(1));
  run.summary = {{"observations", r.observations.size()}, {"laser_scans", scans.size()},
                 {"laser_sensor", laser},                 {"other_laser_scans", other_scans},
                 {"odometry_samples", odometry.size()},   {"dropped_out_of_order", out_of_order}};
}

// The plain-text layout: images stay where they are; the scans (one file each) are gathered into
// one scans file in the artifact. Intrinsics are not in the layout: the calibrate stage gives them.
void run_plain_text(StageRun& run, const SourceConfig& c) {
  Recording r;
  std::vector<LaserScan> scans;
  std::string laser;
  int other_scans = 0;
  for (const auto& o : read_plain_text(c)) {
    const PlainTextEntry& e = o.entry;
    if (!o.scan.empty()) {
      if (laser.empty() && (c.laser_sensor.empty() || e.sensor == c.laser_sensor)) laser = e.sensor;
      if (e.sensor != laser) {
        ++other_scans;
        continue;
      }
      LaserScan scan = parse_plain_text_scan(o.scan.string(), read_file(o.scan), e);
      if (const std::string problem = check_scan(scan); !problem.empty())
        throw InputError({{c.path, e.line, 1, "scan " + e.id + ": " + problem}});
      if (!scans.empty() && scan.timestamp <= scans.back().timestamp)
        throw InputError({{c.path, e.line, 1, "scan " + e.id + ": its timestamp does not increase"}});
      scan.index = static_cast<int>(scans.size());
      scans.push_back(std::move(scan));
      continue;
    }
    if (!safe_sensor_id(e.sensor))
      throw InputError({{c.path, e.line, 1, "sensor label '" + e.sensor + "' cannot name output folders"}});
    const bool known =
        std::any_of(r.sensors.begin(), r.sensors.end(), [&](const SensorInfo& s) { return s.id == e.sensor; });
    if (!known) {
      SensorInfo sensor;
      sensor.id = e.sensor;
      image_size(o.depth, &sensor.depth_width, &sensor.depth_height);
      if (!o.intensity.empty()) image_size(o.intensity, &sensor.color_width, &sensor.color_height);
      SensorCalibration cal;  // intrinsics unknown (fx 0): the calibrate stage must give them
      cal.depth_scale = kPlainTextDepthScale;
      cal.T_robot_sensor = e.sensor_pose * mrpt_camera_from_optical();
      sensor.calibration = cal;
      r.sensors.push_back(sensor);
    }
    Observation observation{e.id, e.sensor, e.timestamp, {o.depth.string(), run.digests.digest(o.depth)}, std::nullopt};
    if (!o.intensity.empty()) observation.color = ImageFile{o.intensity.string(), run.digests.digest(o.intensity)};
    r.observations.push_back(observation);
  }
  std::stable_sort(r.observations.begin(), r.observations.end(), [](const Observation& a, const Observation& b) {
    return a.timestamp < b.timestamp || (a.timestamp == b.timestamp && a.sensor < b.sensor);
  });
  if (!scans.empty()) {
    run.write("laser/scans.txt", format_laser_scans(scans));
    r.laser_scans = "laser/scans.txt";
  }
  if (!c.laser_sensor.empty() && laser.empty())
    throw InputError(c.path, "lists no scan of laser_sensor '" + c.laser_sensor + "'");
  if (r.observations.empty() && scans.empty()) throw InputError(c.path, "lists no observations");
  r.root = plain_text_folder(c).string();
  run.write("recording.json", to_json(r).dump(1));
  run.summary = {{"observations", r.observations.size()}, {"laser_scans", scans.size()},
                 {"laser_sensor", laser}, {"other_laser_scans", other_scans}};
}

// A laser-only recording: the scans and odometry stay where they are.
void run_laser_text(StageRun& run, const SourceConfig& c) {
  const LaserText t = read_laser_text(c);
  Recording r;
  r.laser_scans = fs::absolute(c.scans).string();
  if (!c.odometry.empty()) r.odometry = fs::absolute(c.odometry).string();
  run.write("recording.json", to_json(r).dump(1));
  run.summary = {{"observations", 0}, {"laser_scans", t.scans.size()}, {"odometry_samples", t.odometry.size()}};
}

void run_synthetic(StageRun& run, const SourceConfig& c) {
  SyntheticConfig sc;
  sc.frames = c.frames;
  sc.width = c.width;
  sc.height = c.height;
  sc.rate_hz = c.rate_hz;
  sc.cameras = c.cameras;
  sc.seed = static_cast<unsigned>(c.seed);
  const SyntheticScene scene = make_synthetic_scene(sc);
  const bool robot = sc.cameras > 0;

  Recording r;
  std::vector<std::string> ids = robot ? scene.sensors : std::vector<std::string>{c.sensor};
  for (size_t k = 0; k < ids.size(); ++k) {
    SensorInfo sensor{ids[k], sc.width, sc.height, sc.width, sc.height, SensorCalibration{}};
    sensor.calibration->depth = scene.camera;
    sensor.calibration->color = scene.camera;
    sensor.calibration->depth_scale = sc.depth_scale;
    sensor.calibration->T_robot_sensor = scene.T_robot_camera[k];
    if (robot) sensor.calibration->max_depth_m = 8;  // the Kinect-class range; farther is noise
    r.sensors.push_back(sensor);
  }
  Trajectory truth;
  for (size_t i = 0; i < scene.timestamps.size(); ++i) {
    const SyntheticFrame frame = render_synthetic_frame(scene, i);
    char id[32];
    std::snprintf(id, sizeof(id), "%06zu", i);
    const std::string depth = std::string("depth/") + id + ".png", color = std::string("rgb/") + id + ".png";
    const std::string depth_png = encode_png(frame.depth), color_png = encode_png(frame.color);
    run.write(depth, depth_png);
    run.write(color, color_png);
    run.write(std::string("groundtruth/objects/") + id + ".png", encode_png(frame.object));
    const std::string& sensor = ids[static_cast<size_t>(scene.camera_of[i])];
    r.observations.push_back(
        {id, sensor, scene.timestamps[i], {depth, sha256_hex(depth_png)}, ImageFile{color, sha256_hex(color_png)}});
    truth.push_back({scene.timestamps[i], scene.T_world_camera[i]});
  }
  if (robot) {  // the truth is the robot's; each camera's follows from its pose on the robot
    truth = scene.robot_truth;
    r.groundtruth_frame = "robot";
    run.write("laser/scans.txt", format_laser_scans(scene.scans));
    run.write("laser/odometry.txt", format_odometry(scene.odometry));
    r.laser_scans = "laser/scans.txt";
    r.odometry = "laser/odometry.txt";
  }
  run.write("groundtruth/trajectory.txt", format_tum_trajectory(truth));
  run.write("groundtruth/boxes.json", format_native_annotations(scene.annotations));
  r.groundtruth = "groundtruth/trajectory.txt";
  r.boxes = "groundtruth/boxes.json";
  run.write("recording.json", to_json(r).dump(1));
  run.summary = {{"observations", r.observations.size()}};
  if (robot) {
    run.summary["laser_scans"] = scene.scans.size();
    run.summary["odometry_samples"] = scene.odometry.size();
  }
}

// Every listed image exists, is a PNG of a readable size, depth 16-bit grey, and each list's images
// share one size: found before anything runs, at the list's line.
void check_tum_images(const fs::path& dir, std::vector<Diagnostic>& errors) {
  TumLists lists;
  try {
    lists = read_tum_lists(dir);
  } catch (const InputError& e) {
    errors.insert(errors.end(), e.diagnostics().begin(), e.diagnostics().end());
    return;
  }
  if (lists.depth.empty()) {
    errors.push_back({(dir / "depth.txt").string(), 0, 0, "lists no depth images"});
    return;
  }
  for (const bool depth : {true, false}) {
    const std::string list = (dir / (depth ? "depth.txt" : "rgb.txt")).string();
    std::optional<PngHeader> first;
    for (const auto& e : depth ? lists.depth : lists.color) {
      const auto problem = [&](const std::string& what) {
        errors.push_back({list, e.line, 1, (depth ? "depth image " : "colour image ") + e.file + ": " + what});
      };
      PngHeader header;
      try {
        header = read_png_header(resolve_path(dir, e.file));
      } catch (const InputError& error) {
        problem(error.diagnostics().front().message);
        continue;
      }
      if (depth && !header.grey16()) problem("expected a 16-bit single-channel PNG, found " + header.describe());
      if (!first) {
        first = header;
      } else if (header.width != first->width || header.height != first->height) {
        problem("is " + std::to_string(header.width) + "x" + std::to_string(header.height) + ", the list's first is " +
                std::to_string(first->width) + "x" + std::to_string(first->height));
      }
    }
  }
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>&, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const SourceConfig c = params()->from_json(stage.params);
  const std::string at = stage.pointer + "/params";
  const nlohmann::json& given =
      doc.value.at(nlohmann::json::json_pointer(stage.pointer)).value("params", nlohmann::json::object());
  if (!safe_sensor_id(c.sensor))
    errors.push_back(doc.error_at(at + "/sensor", "stage '" + stage.id + "' (source): sensor id '" + c.sensor +
                                                      "' must start with a letter, digit or '_' and hold only those, "
                                                      "'.' and '-' (it names output folders)"));
  if (c.format == "tum") {
    if (c.path.empty()) {
      errors.push_back(
          doc.error_at(at, "stage '" + stage.id + "' (source): format tum needs 'path', the dataset folder"));
      return;
    }
    bool lists_exist = true;
    for (const char* list : {"depth.txt", "rgb.txt"})
      if (!fs::exists(fs::path(c.path) / list)) {
        lists_exist = false;
        errors.push_back(doc.error_at(
            at + "/path", "stage '" + stage.id + "' (source): " + (fs::path(c.path) / list).string() + " not found"));
      }
    if (lists_exist) check_tum_images(c.path, errors);
  } else if (c.format == "plain_text") {
    if (c.path.empty() || !fs::is_regular_file(c.path))
      errors.push_back(
          doc.error_at(at, "stage '" + stage.id + "' (source): format plain_text needs 'path', the sequence file"));
  } else if (c.format == "rawlog") {
    if (!rawlog_supported())
      errors.push_back(doc.error_at(at + "/format", "stage '" + stage.id +
                                                        "' (source): format rawlog needs libmrpt; this olt was built "
                                                        "without it (install libmrpt-obs-dev and rebuild)"));
    else if (c.path.empty() || !fs::is_regular_file(c.path))
      errors.push_back(doc.error_at(at, "stage '" + stage.id + "' (source): format rawlog needs 'path', the .rawlog file"));
  } else if (given.is_object() && given.contains("path")) {
    errors.push_back(doc.error_at_key(at + "/path",
                                      "stage '" + stage.id + "' (source): 'path' applies to formats tum, rawlog and plain_text only"));
  }
  if (c.format == "synthetic" && c.cameras > 0 && c.frames / c.rate_hz > 3600)
    errors.push_back(doc.error_at(at, "stage '" + stage.id + "' (source): a synthetic robot drives at most an hour: " +
                                          "frames / rate_hz is " + std::to_string(c.frames / c.rate_hz) + " s"));
  if (c.format == "laser_text" && c.scans.empty())
    errors.push_back(doc.error_at(at, "stage '" + stage.id + "' (source): format laser_text needs 'scans', the scans file"));
  // Parameters of another format are a mistake worth naming.
  const std::pair<const char*, std::vector<std::string>> owners[] = {
      {"scans", {"laser_text"}},
      {"odometry", {"laser_text"}},
      {"observations", {"plain_text"}},
      {"laser_sensor", {"rawlog", "plain_text"}},
      {"cameras", {"synthetic"}},
      {"seed", {"synthetic"}}};
  for (const auto& [key, formats] : owners)
    if (given.is_object() && given.contains(key) &&
        std::find(formats.begin(), formats.end(), c.format) == formats.end())
      errors.push_back(doc.error_at_key(at + "/" + key, "stage '" + stage.id + "' (source): '" + key +
                                                            "' applies to format " + formats.front() +
                                                            (formats.size() > 1 ? " and " + formats.back() : "") +
                                                            " only"));
}

void run(StageRun& run) {
  const SourceConfig c = params()->from_json(run.stage.params);
  if (c.format == "synthetic")
    run_synthetic(run, c);
  else if (c.format == "laser_text")
    run_laser_text(run, c);
  else if (c.format == "rawlog")
    run_rawlog(run, c);
  else if (c.format == "plain_text")
    run_plain_text(run, c);
  else
    run_tum(run, c);
}

}  // namespace

StageKind source_kind() { return {{"source", params(), {}, {}, check}, 3, files_read, run}; }

}  // namespace olt
