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
                "synthetic: colour images taken this long after depth, alternating sign, seconds")
        .number("tilt_deg", &SourceConfig::tilt_deg, between(0, 90),
                "synthetic hand-held: the poses' and boxes' frame tilted this far from gravity, degrees");
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

// Where the problems of one source stage go, and how they are worded.
struct SourceCheck {
  const StageDecl& stage;
  const Document& doc;
  std::vector<Diagnostic>& errors;
  const std::string at;  ///< the params' pointer
  void fail(const std::string& where, const std::string& problem, bool at_key = false) const {
    const std::string message = "stage '" + stage.id + "' (source): " + problem;
    errors.push_back(at_key ? doc.error_at_key(where, message) : doc.error_at(where, message));
  }
};

// The path each format needs (tum: the folder with its lists; plain_text, rawlog: the file).
void check_path(const SourceConfig& c, const nlohmann::json& given, const SourceCheck& check) {
  const std::string& at = check.at;
  // A path given but refused (it does not exist) was said by the parameter itself.
  if (c.path.empty() && given.is_object() && given.contains("path")) return;
  if (c.format == SourceFormat::tum) {
    if (c.path.empty()) return check.fail(at, "format tum needs 'path', the dataset folder");
    bool lists_exist = true;
    for (const char* list : {"depth.txt", "rgb.txt"})
      if (!fs::exists(fs::path(c.path) / list)) {
        lists_exist = false;
        check.fail(at + "/path", (fs::path(c.path) / list).string() + " not found");
      }
    if (lists_exist) source::check_tum_images(c.path, check.errors);
  } else if (c.format == SourceFormat::plain_text) {
    if (c.path.empty() || !fs::is_regular_file(c.path))
      check.fail(at, "format plain_text needs 'path', the sequence file");
  } else if (c.format == SourceFormat::rawlog) {
    if (!rawlog_supported())
      check.fail(at + "/format", kRawlogNeedsMrpt);
    else if (c.path.empty() || !fs::is_regular_file(c.path))
      check.fail(at, "format rawlog needs 'path', the .rawlog file");
  } else if (given.is_object() && given.contains("path")) {
    check.fail(at + "/path", "'path' applies to formats tum, rawlog and plain_text only", true);
  }
}

// What the other formats need, and parameters of another format (a mistake worth naming).
void check_format_params(const SourceConfig& c, const nlohmann::json& given, const SourceCheck& check) {
  const std::string& at = check.at;
  if (c.format == SourceFormat::synthetic && c.cameras > 0 && c.frames / c.rate_hz > 3600)
    check.fail(at, "a synthetic robot drives at most an hour: frames / rate_hz is " +
                       std::to_string(c.frames / c.rate_hz) + " s");
  if (c.format == SourceFormat::synthetic && c.cameras > 0 && c.tilt_deg != 0)
    check.fail(at + "/tilt_deg", "'tilt_deg' applies to the hand-held camera (cameras: 0): a robot's laser is level",
               true);
  if (c.format == SourceFormat::laser_text && c.scans.empty())
    check.fail(at, "format laser_text needs 'scans', the scans file");
  const std::pair<const char*, std::vector<std::string>> owners[] = {
      {"scans", {"laser_text"}},        {"odometry", {"laser_text"}},
      {"observations", {"plain_text"}}, {"laser_sensor", {"rawlog", "plain_text"}},
      {"cameras", {"synthetic"}},       {"seed", {"synthetic"}},
      {"color_dt_s", {"synthetic"}},    {"tilt_deg", {"synthetic"}}};
  for (const auto& [key, formats] : owners)
    if (given.is_object() && given.contains(key) &&
        std::find(formats.begin(), formats.end(), source::name_of(c.format)) == formats.end())
      check.fail(at + "/" + key,
                 std::string("'") + key + "' applies to format " + formats.front() +
                     (formats.size() > 1 ? " and " + formats.back() : "") + " only",
                 true);
}

void check(const StageDecl& stage, const std::map<std::string, const StageDecl*>&, const Document& doc,
           std::vector<Diagnostic>& errors) {
  const SourceConfig c = params()->from_json(stage.params);
  const SourceCheck source_check{stage, doc, errors, stage.pointer + "/params"};
  const nlohmann::json& given =
      doc.value.at(nlohmann::json::json_pointer(stage.pointer)).value("params", nlohmann::json::object());
  if (!source::safe_id(c.sensor))
    source_check.fail(source_check.at + "/sensor", "sensor id '" + c.sensor +
                                                       "' must start with a letter, digit or '_' and hold only those, "
                                                       "'.' and '-' (it names output folders)");
  check_path(c, given, source_check);
  check_format_params(c, given, source_check);
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

StageKind source_kind() { return make_stage_kind({"source", params(), {}, {}, check}, 4, files_read, run); }

}  // namespace olt
