// `source` format plain_text: the OLT / Robot@Home plain-text layout (formats/plain_text_layout.h).
#include <algorithm>
#include <map>
#include <optional>
#include <set>

#include "olt/core/image.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/plain_text_layout.h"
#include "olt/model/recording.h"
#include "source_formats.h"

namespace olt::source {
namespace {

// Each entry of the sequence file with its files, checked at the sequence file's line.
struct PlainTextObservation {
  PlainTextEntry entry;
  fs::path scan, depth, intensity;  ///< those that exist
};

fs::path plain_text_folder(const SourceConfig& c) {
  if (!c.observations.empty()) return c.observations;
  fs::path folder = c.path;
  return folder.replace_extension();
}

// An RGB-D observation's images: a 16-bit depth image, and the size of its sensor's first ones (with
// an intensity image where they had one). `first` holds each sensor's first images' headers.
void check_images(const PlainTextObservation& o, const SourceConfig& c,
                  std::map<std::string, std::pair<ImageHeader, std::optional<ImageHeader>>>& first) {
  const PlainTextEntry& e = o.entry;
  const ImageHeader depth = read_image_header(o.depth);
  if (!depth.grey16())
    throw InputError(
        {{c.path, e.line, 1,
          o.depth.string() + ": expected a 16-bit single-channel image (PNG or TIFF), found " + depth.describe()}});
  std::optional<ImageHeader> intensity;
  if (!o.intensity.empty()) intensity = read_image_header(o.intensity);
  const auto [known, inserted] = first.emplace(e.sensor, std::make_pair(depth, intensity));
  const auto same = [](const ImageHeader& a, const ImageHeader& b) {
    return a.width == b.width && a.height == b.height;
  };
  if (!inserted && (!same(known->second.first, depth) || intensity.has_value() != known->second.second.has_value() ||
                    (intensity && !same(*known->second.second, *intensity))))
    throw InputError({{c.path, e.line, 1,
                       "observation " + e.id + ": its images are not the size of sensor " + e.sensor +
                           "'s first ones (or it lacks the intensity image they have)"}});
}

// The sequence's entries with their files: a scan, or depth (and intensity) images.
std::vector<PlainTextObservation> read_plain_text(const SourceConfig& c) {
  const fs::path folder = plain_text_folder(c);
  std::vector<PlainTextObservation> out;
  std::set<std::string> ids;
  std::map<std::string, std::pair<ImageHeader, std::optional<ImageHeader>>> first_images;  // by sensor
  for (const auto& e : parse_plain_text_sequence(c.path, read_file(c.path))) {
    // Ids name the observation's files here and its outputs later: nothing that could leave a folder.
    if (!safe_id(e.id))
      throw InputError(
          {{c.path, e.line, 1,
            "observation id '" + e.id + "' must hold only letters, digits, '_', '.' and '-' (it names files)"}});
    if (!ids.insert(e.id).second) throw InputError({{c.path, e.line, 1, "observation id '" + e.id + "' repeats"}});
    PlainTextObservation o{e, folder / (e.id + "_scan.txt"), folder / (e.id + "_depth.png"),
                           folder / (e.id + "_intensity.png")};
    for (fs::path* file : {&o.scan, &o.depth, &o.intensity})
      if (!fs::exists(*file)) file->clear();
    if (o.scan.empty() && o.depth.empty())
      throw InputError({{c.path, e.line, 1,
                         "observation " + e.id + ": neither " + (folder / (e.id + "_scan.txt")).string() + " nor " +
                             (folder / (e.id + "_depth.png")).string() + " exists"}});
    if (o.scan.empty()) check_images(o, c, first_images);
    out.push_back(o);
  }
  return out;
}

// An RGB-D sensor of the layout, from its first observation: image sizes, depth in millimetres and
// its pose on the robot; no intrinsics (fx 0: the calibrate stage must give them).
SensorInfo plain_text_sensor(const PlainTextObservation& o) {
  SensorInfo sensor;
  sensor.id = o.entry.sensor;
  image_size(o.depth, &sensor.depth_width, &sensor.depth_height);
  if (!o.intensity.empty()) image_size(o.intensity, &sensor.color_width, &sensor.color_height);
  SensorCalibration cal;
  cal.depth_scale = kPlainTextDepthScale;
  cal.T_robot_sensor = o.entry.sensor_pose * mrpt_camera_from_optical();
  sensor.calibration = cal;
  return sensor;
}

// The observation's scan, checked and after the scans before it in time.
LaserScan read_scan(const PlainTextObservation& o, const SourceConfig& c, const std::vector<LaserScan>& before) {
  const PlainTextEntry& e = o.entry;
  LaserScan scan = parse_plain_text_scan(o.scan.string(), read_file(o.scan), e);
  if (const std::string problem = check_scan(scan); !problem.empty())
    throw InputError({{c.path, e.line, 1, "scan " + e.id + ": " + problem}});
  if (!before.empty() && scan.timestamp <= before.back().timestamp)
    throw InputError({{c.path, e.line, 1, "scan " + e.id + ": its timestamp does not increase"}});
  scan.index = static_cast<int>(before.size());
  return scan;
}

}  // namespace

std::vector<fs::path> plain_text_files(const SourceConfig& c) {
  std::vector<fs::path> files = {c.path};
  for (const auto& o : read_plain_text(c)) {
    for (const fs::path& f : {o.scan, o.depth, o.intensity})
      if (!f.empty()) files.push_back(f);
    if (o.scan.empty()) continue;
    LaserScan scan = parse_plain_text_scan(o.scan.string(), read_file(o.scan), o.entry);
    if (const std::string problem = check_scan(scan); !problem.empty())
      throw InputError({{c.path, o.entry.line, 1, "scan " + o.entry.id + ": " + problem}});
  }
  return files;
}

// The plain-text layout: images stay where they are; the scans (one file each) are gathered into
// one scans file in the artifact. Intrinsics are not in the layout: the calibrate stage gives them.
nlohmann::json run_plain_text(const StageContext& ctx, ArtifactWriter& out, const SourceConfig& c) {
  Recording r;
  std::vector<LaserScan> scans;
  std::string laser;
  int other_scans = 0;
  for (const auto& o : read_plain_text(c)) {
    const PlainTextEntry& e = o.entry;
    if (!o.scan.empty()) {
      if (laser.empty() && (c.laser_sensor.empty() || e.sensor == c.laser_sensor)) laser = e.sensor;
      if (e.sensor == laser)
        scans.push_back(read_scan(o, c, scans));
      else
        ++other_scans;
      continue;
    }
    if (!safe_id(e.sensor))
      throw InputError({{c.path, e.line, 1, "sensor label '" + e.sensor + "' cannot name output folders"}});
    if (std::none_of(r.sensors.begin(), r.sensors.end(), [&](const SensorInfo& s) { return s.id == e.sensor; }))
      r.sensors.push_back(plain_text_sensor(o));
    Observation observation{
        e.id, e.sensor, e.timestamp, {o.depth.string(), Digest(ctx.digest_file(o.depth))}, std::nullopt};
    if (!o.intensity.empty()) observation.color = ImageFile{o.intensity.string(), Digest(ctx.digest_file(o.intensity))};
    r.observations.push_back(observation);
  }
  sort_by_time(r.observations);
  if (!scans.empty()) {
    out.write("laser/scans.txt", format_laser_scans(scans));
    r.laser_scans = "laser/scans.txt";
  }
  if (!c.laser_sensor.empty() && laser.empty())
    throw InputError(c.path, "lists no scan of laser_sensor '" + c.laser_sensor + "'");
  if (r.observations.empty() && scans.empty()) throw InputError(c.path, "lists no observations");
  r.root = plain_text_folder(c).string();
  write_recording(out, r);
  return {{"observations", r.observations.size()},
          {"laser_scans", scans.size()},
          {"laser_sensor", laser},
          {"other_laser_scans", other_scans}};
}

}  // namespace olt::source
