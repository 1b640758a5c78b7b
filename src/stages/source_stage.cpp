// `source`: reads a recording into an index of observations (images stay where they are and are
// identified by content hash), or generates the built-in synthetic recording. The formats live in
// source_<format>.cpp; this file holds the parameters, validation and dispatch.
#include <algorithm>

#include "olt/formats/rawlog.h"
#include "olt/stages/kinds.h"
#include "source_formats.h"

namespace olt {
namespace {

using source::SourceConfig;
using source::SourceFormat;

std::shared_ptr<const Params<SourceConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<SourceConfig>>();
    t->choice("format", &SourceConfig::format, source::source_format_names(), "recording layout")
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
        .integer("seed", &SourceConfig::seed, between(0, 2147483647), "synthetic robot: noise and odometry drift")
        .number("color_dt_s", &SourceConfig::color_dt_s, between(-0.1, 0.1),
                "synthetic: colour images taken this long after depth, alternating sign, seconds");
    return t;
  }();
  return p;
}

std::vector<fs::path> files_read(const StageDecl& stage) {
  const SourceConfig c = params()->from_json(stage.params);
  if (c.format == SourceFormat::tum) return source::tum_files(c);
  if (c.format == SourceFormat::plain_text) return source::plain_text_files(c);
  if (c.format == SourceFormat::laser_text) return source::laser_text_files(c);
  if (c.format == SourceFormat::rawlog) return {c.path};
  return {};
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>&, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const SourceConfig c = params()->from_json(stage.params);
  const std::string at = stage.pointer + "/params";
  const nlohmann::json& given =
      doc.value.at(nlohmann::json::json_pointer(stage.pointer)).value("params", nlohmann::json::object());
  if (!source::safe_id(c.sensor))
    errors.push_back(doc.error_at(at + "/sensor", "stage '" + stage.id + "' (source): sensor id '" + c.sensor +
                                                      "' must start with a letter, digit or '_' and hold only those, "
                                                      "'.' and '-' (it names output folders)"));
  if (c.format == SourceFormat::tum) {
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
    if (lists_exist) source::check_tum_images(c.path, errors);
  } else if (c.format == SourceFormat::plain_text) {
    if (c.path.empty() || !fs::is_regular_file(c.path))
      errors.push_back(
          doc.error_at(at, "stage '" + stage.id + "' (source): format plain_text needs 'path', the sequence file"));
  } else if (c.format == SourceFormat::rawlog) {
    if (!rawlog_supported())
      errors.push_back(doc.error_at(at + "/format", "stage '" + stage.id +
                                                        "' (source): format rawlog needs libmrpt; this olt was built "
                                                        "without it (install libmrpt-obs-dev and rebuild)"));
    else if (c.path.empty() || !fs::is_regular_file(c.path))
      errors.push_back(
          doc.error_at(at, "stage '" + stage.id + "' (source): format rawlog needs 'path', the .rawlog file"));
  } else if (given.is_object() && given.contains("path")) {
    errors.push_back(doc.error_at_key(
        at + "/path", "stage '" + stage.id + "' (source): 'path' applies to formats tum, rawlog and plain_text only"));
  }
  if (c.format == SourceFormat::synthetic && c.cameras > 0 && c.frames / c.rate_hz > 3600)
    errors.push_back(doc.error_at(at, "stage '" + stage.id + "' (source): a synthetic robot drives at most an hour: " +
                                          "frames / rate_hz is " + std::to_string(c.frames / c.rate_hz) + " s"));
  if (c.format == SourceFormat::laser_text && c.scans.empty())
    errors.push_back(
        doc.error_at(at, "stage '" + stage.id + "' (source): format laser_text needs 'scans', the scans file"));
  // Parameters of another format are a mistake worth naming.
  const std::pair<const char*, std::vector<std::string>> owners[] = {
      {"scans", {"laser_text"}},        {"odometry", {"laser_text"}},
      {"observations", {"plain_text"}}, {"laser_sensor", {"rawlog", "plain_text"}},
      {"cameras", {"synthetic"}},       {"seed", {"synthetic"}},
      {"color_dt_s", {"synthetic"}}};
  for (const auto& [key, formats] : owners)
    if (given.is_object() && given.contains(key) &&
        std::find(formats.begin(), formats.end(), source::name_of(c.format)) == formats.end())
      errors.push_back(doc.error_at_key(
          at + "/" + key, "stage '" + stage.id + "' (source): '" + key + "' applies to format " + formats.front() +
                              (formats.size() > 1 ? " and " + formats.back() : "") + " only"));
}

nlohmann::json run(const StageContext& ctx, ArtifactWriter& out) {
  const SourceConfig c = params()->from_json(ctx.stage.params);
  if (c.format == SourceFormat::synthetic) return source::run_synthetic(ctx, out, c);
  if (c.format == SourceFormat::laser_text) return source::run_laser_text(ctx, out, c);
  if (c.format == SourceFormat::rawlog) return source::run_rawlog(ctx, out, c);
  if (c.format == SourceFormat::plain_text) return source::run_plain_text(ctx, out, c);
  return source::run_tum(ctx, out, c);
}

}  // namespace

StageKind source_kind() { return make_stage_kind({"source", params(), {}, {}, check}, 3, files_read, run); }

}  // namespace olt
