// `report`: one HTML page and its pictures, for a person to see in ten seconds whether the labels
// are right: the class legend and per-class and per-instance counts, the boxes' warnings, every
// frame's labeled share and pose consistency with the worst and the flagged marked (report_frames.h),
// the trajectory, the levelled scene with every box and a picture around each box (when a
// reconstruct stage is upstream; report_boxes.h), and overlay tiles linked to the full overlays.
#include <algorithm>
#include <cstdio>
#include <map>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/core/made_once.h"
#include "olt/core/parallel.h"
#include "olt/core/process_memory.h"
#include "olt/reconstruct/level.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
#include "olt/stages/report.h"
#include "olt/stages/sentences.h"
#include "olt/stages/typed_stage.h"
#include "report_boxes.h"
#include "report_frames.h"

namespace olt {
namespace {

std::shared_ptr<const Params<ReportConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<ReportConfig>>();
    t->integer("contact_sheet_frames", &ReportConfig::contact_sheet_frames, between(1, 400),
               "overlays on the contact sheet, evenly spread")
        .integer("tile_width_px", &ReportConfig::tile_width_px, between(40, 2000), "width of one overlay on the sheet")
        .integer("worst_frames", &ReportConfig::worst_frames, between(0, 100),
                 "frames listed whose labeled share is lowest against their neighbours'")
        .integer("scene_picture_px", &ReportConfig::scene_picture_px, between(100, 4000),
                 "height of the scene with its boxes, pixels")
        .integer("box_picture_px", &ReportConfig::box_picture_px, between(100, 2000),
                 "height of each box's picture, pixels");
    return t;
  }();
  return p;
}

// A frame's overlay shrunk to a tile's width, JPEG; remembered by the overlay's digest and the width.
std::string tile_of(const ReportInputs& in, const ReportFrame& f, const ReportConfig& c) {
  const ListedFile overlay = in.labels->files[*f.overlay];
  const fs::path path = in.labels->path(overlay);
  // 2: decoded at a DCT scale of the overlay (1/2 of a 640-pixel overlay for a 240-pixel tile).
  const nlohmann::json record = {{"tile", 2}, {"overlay", overlay.sha256.hex()}, {"width_px", c.tile_width_px}};
  const auto draw = [&] {
    cv::Mat image = decode_color_shrunk(in.read(path), path.string(), c.tile_width_px), tile;
    const double scale = static_cast<double>(c.tile_width_px) / image.cols;
    cv::resize(image, tile, cv::Size(), scale, scale, cv::INTER_AREA);
    return encode_jpeg(tile);
  };
  return overlay.sha256.empty() ? draw() : in.memo(record, draw);
}

// A tile and its caption, linked to the full overlay.
std::string tile_html(const ReportInputs& in, const ReportFrame& f, const std::string& file,
                      const std::string& caption) {
  const std::string img = "<img src=\"" + file + "\" alt=\"" + html_escape(f.name()) + "\">";
  const std::string link = overlay_link(in, f);
  return "<figure class=\"tile\">" + (link.empty() ? img : "<a href=\"" + html_escape(link) + "\">" + img + "</a>") +
         "<figcaption>" + caption + "</figcaption></figure>\n";
}

// The tiles the page shows (worst frames and the contact sheet's evenly spread frames), each drawn
// once; their HTML sections.
struct Tiles {
  std::string worst, sheet;
};

Tiles draw_tiles(const ReportInputs& in, const ReportConfig& c, const std::vector<size_t>& worst,
                 ReportResult& result) {
  std::vector<size_t> with_overlay;
  for (size_t i = 0; i < in.frames.size(); ++i)
    if (in.frames[i].overlay) with_overlay.push_back(i);
  std::map<size_t, std::string> drawn;  // frame -> tile file
  std::vector<size_t> order;            // the frames drawn, in the page's order
  auto tile = [&](size_t i) {
    auto [it, fresh] = drawn.emplace(i, "tiles/" + std::to_string(i) + ".jpg");
    if (fresh) order.push_back(i);
    return it->second;
  };
  Tiles out;
  for (size_t i : worst) {
    const ReportFrame& f = in.frames[i];
    const std::string caption = html_escape(f.name()) + ": " + percent(f.labeled_pixels, f.depth_pixels) +
                                " labeled, " + percent(share_against_neighbours(in.frames, i), 1) +
                                " of its neighbours' share" +
                                (f.consistency ? ", consistency " + percent(*f.consistency, 1) : "");
    out.worst += f.overlay ? tile_html(in, f, tile(i), caption) : "<p>" + caption + "</p>\n";
  }
  const size_t count = std::min(with_overlay.size(), static_cast<size_t>(c.contact_sheet_frames));
  for (size_t k = 0; k < count; ++k) {
    const size_t i = with_overlay[k * with_overlay.size() / count];
    out.sheet += tile_html(in, in.frames[i], tile(i), html_escape(in.frames[i].name()));
  }
  std::vector<std::string> jpeg(order.size());
  parallel_for(order.size(), [&](size_t k) { jpeg[k] = tile_of(in, in.frames[order[k]], c); });
  for (size_t k = 0; k < order.size(); ++k) result.pictures.emplace_back(drawn.at(order[k]), std::move(jpeg[k]));
  return out;
}

// Class legend (colour, id, pixels and their share, frames), instances, the boxes' warnings.
std::string tables(const ReportInputs& in) {
  const auto row = [](const std::vector<std::string>& cells) {
    std::string html = "<tr>";
    for (const auto& cell : cells) html += "<td>" + cell + "</td>";
    return html + "</tr>\n";
  };
  const nlohmann::json& summary = in.labels_summary;
  // Named: a range over a temporary's items() would dangle.
  const nlohmann::json listed = summary.value("warnings", nlohmann::json::array()),
                       class_counts = summary.value("classes", nlohmann::json::object()),
                       instance_counts = summary.value("instances", nlohmann::json::object());
  std::string warnings;
  for (const auto& w : listed) warnings += "<li>" + html_escape(w.get<std::string>()) + "</li>\n";
  int64_t labeled = 0;
  for (const auto& [name, counts] : class_counts.items()) labeled += counts.value("pixels", int64_t{0});
  std::string classes;
  for (const auto& c : in.label_map.classes) {
    const nlohmann::json counts = class_counts.value(c.name, nlohmann::json::object());
    const int64_t pixels = counts.value("pixels", int64_t{0});
    classes +=
        row({"<span class=\"swatch\" style=\"background:" + hex_colour(c.color) + "\"></span>" + html_escape(c.name),
             std::to_string(c.id), hex_colour(c.color), std::to_string(pixels), percent(pixels, labeled),
             std::to_string(counts.value("frames", 0))});
  }
  std::string instances;
  for (const auto& [name, counts] : instance_counts.items()) {
    std::string boxes;
    for (const auto& b : counts.value("boxes", nlohmann::json::array()))
      boxes += (boxes.empty() ? "" : " ") + b.get<std::string>();
    instances += row({html_escape(name), html_escape(counts.value("label", "")), html_escape(boxes),
                      std::to_string(counts.value("pixels", 0)), std::to_string(counts.value("frames", 0))});
  }
  return "<h2>Boxes to check</h2>\n<ul>\n" + (warnings.empty() ? "<li>none</li>\n" : warnings) +
         "</ul>\n<h2>Classes</h2>\n<table><tr><th>class</th><th>id</th><th>colour</th><th>pixels</th>"
         "<th>share of labeled pixels</th><th>frames</th></tr>\n" +
         classes +
         "</table>\n<h2>Instances</h2>\n<table><tr><th>instance</th><th>class</th><th>boxes</th><th>pixels</th>"
         "<th>frames</th></tr>\n" +
         instances + "</table>\n";
}

// The frames whose labeled share is lowest against their neighbours' (none asked: no section).
std::string worst_section(const ReportConfig& c, const Tiles& tiles) {
  if (c.worst_frames == 0) return "";
  return "<h3>Worst frames</h3>\n<p>Frames whose labeled share is well under their neighbours' (a box that "
         "misses, or a pose off): click a picture for the full overlay.</p>\n" +
         (tiles.worst.empty() ? "<p>none: every frame labels about as much as its neighbours.</p>\n" : tiles.worst);
}

// The flagged observations, the first 50 named.
std::string flagged_list(const ReportInputs& in) {
  std::string items;
  size_t n = 0;
  for (const auto& f : in.frames)
    if (!f.pose_valid && n++ < 50) items += "<li>" + html_escape(f.name() + ": " + f.flag()) + "</li>\n";
  if (n > 50) items += "<li>and " + std::to_string(n - 50) + " more (poses/ in the output lists all)</li>\n";
  return "<h2>Flagged observations</h2>\n<p>" + std::to_string(n) + " of " + std::to_string(in.frames.size()) + " (" +
         percent(n, in.frames.size()) + "): their poses are not trusted and they are not labeled.</p>\n<ul>\n" +
         (items.empty() ? "<li>none</li>\n" : items) + "</ul>\n";
}

}  // namespace

ReportResult run_report(const ReportInputs& in, const ReportConfig& c) {
  const nlohmann::json& summary = in.labels_summary;
  ReportResult result;
  int64_t labeled = 0, depth = 0, skipped = 0;
  for (const auto& f : in.frames) {
    labeled += f.labeled_pixels, depth += f.depth_pixels;
    skipped += !f.labeled;
  }
  const std::vector<size_t> worst = worst_frames(in.frames, c.worst_frames);
  // The tiles and the boxes' pictures drawn at the same time: after an edit, a few of each are drawn
  // again (a picture a thread), and neither waits for the other's last one.
  Tiles tiles;
  BoxPictures boxes;
  parallel_for(2, [&](size_t part) {
    if (part == 0)
      tiles = draw_tiles(in, c, worst, result);  // the only one adding to result.pictures meanwhile
    else
      boxes = draw_box_pictures(in, c);
  });
  const std::string trajectory = trajectory_svg(*in.poses);
  for (auto& [file, bytes] : boxes.files) result.pictures.emplace_back(file, std::move(bytes));
  const std::string name = html_escape(in.job_file.stem().string());

  result.html =
      "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>OLT report: " + name +
      "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:1400px}"
      "figure{display:inline-block;margin:0 1em 1em 0;vertical-align:top}"
      "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}"
      "td:first-child{text-align:left}.swatch{display:inline-block;width:1em;height:1em;margin-right:.4em;"
      "vertical-align:middle;border:1px solid "
      "#888}.picture{position:relative;display:inline-block;vertical-align:top}.picture img{display:block}"
      ".picture svg{position:absolute;left:0;top:0;width:100%;height:100%;pointer-events:none}"
      ".picture path{pointer-events:visibleStroke}.tile{width:" +
      std::to_string(c.tile_width_px) +
      "px;margin:0 .5em .5em 0}.tile img{width:100%}"
      ".tile figcaption{font-size:80%;color:#444}</style>\n<link rel=\"icon\" href=\"data:,\"></head><body>\n<h1>" +
      name + "</h1>\n<p>" + std::to_string(in.frames.size() - skipped) + " of " + std::to_string(in.frames.size()) +
      " observations labeled" + (skipped ? " (" + std::to_string(skipped) + " skipped: flagged poses)" : "") + "; " +
      percent(labeled, depth) + " of their depth pixels inside a box, " +
      percent(summary.value("ambiguous_pixels", int64_t{0}), depth) + " inside more than one.</p>\n" + tables(in) +
      "<h2>Frames</h2>\n" + frames_plot_svg(in, worst) + worst_section(c, tiles) + flagged_list(in) +
      (trajectory.empty() ? ""
                          : "<h2>Trajectory</h2>\n<figure>" + trajectory +
                                "<figcaption>the sensor's path from above (world x right, y up); red: flagged "
                                "observations, at the nearest valid pose in time</figcaption></figure>\n") +
      boxes.html + "<h2>Overlays</h2>\n" +
      (tiles.sheet.empty()
           ? "<p>No overlays (propagate's <code>overlays</code> is off).</p>\n"
           : "<p>Evenly spread over the recording; click one for the full overlay.</p>\n" + tiles.sheet) +
      "</body></html>\n";
  return result;
}

std::string overlay_link(const ReportInputs& in, const ReportFrame& f) {
  return f.overlay ? url_path(in.labels_folder + std::string(in.labels->files[*f.overlay].path)) : "";
}

namespace {

// The report looks up the labeling stage's own files and its overlays, not the rest of the files it
// refers to (70,000 at 10,000 frames): what the run holds of its list while the report runs.
bool looked_up_in_labels(const ListedFile& f) { return !referred_file(f) || is_overlay_file(f.path); }

// Each frame's labeled and depth pixels from the labeling stage's frame_pixels.json
// ({"SENSOR/OBSERVATION": [labeled, depth], ...}), taken from the parser's events: no member is
// kept (as a tree, 10,000 frames' took 1.8 MB). Throws std::runtime_error naming `file` for another
// kind of JSON document.
void read_frame_pixels(const fs::path& file, std::vector<ReportFrame>& frames) {
  using Event = nlohmann::json::parse_event_t;
  std::vector<std::pair<std::string, size_t>> by_name;  // "SENSOR/OBSERVATION", the frame's place
  by_name.reserve(frames.size());
  for (size_t i = 0; i < frames.size(); ++i)
    by_name.emplace_back(frames[i].observation->sensor + "/" + frames[i].observation->id, i);
  std::sort(by_name.begin(), by_name.end());
  using Named = std::vector<std::pair<std::string, size_t>>::const_iterator;
  std::pair<Named, Named> named(by_name.end(), by_name.end());  // the frames of the member being parsed
  size_t values = 0;                                            // its numbers so far
  const nlohmann::json rest =
      nlohmann::json::parse(*open_file_stream(file), [&](int depth, Event event, nlohmann::json& parsed) {
        if (depth == 1 && event == Event::key) {
          const std::string name = parsed.get<std::string>();
          named = std::equal_range(by_name.begin(), by_name.end(), std::make_pair(name, size_t{0}),
                                   [](const auto& a, const auto& b) { return a.first < b.first; });
          values = 0;
          return false;  // the member is not kept: its numbers come as events
        }
        if (depth == 2 && event == Event::value && parsed.is_number_integer() && values < 2) {
          for (Named at = named.first; at != named.second; ++at) {
            ReportFrame& f = frames[at->second];
            f.labeled = true;
            (values == 0 ? f.labeled_pixels : f.depth_pixels) = parsed.get<int64_t>();
          }
          ++values;
        }
        return true;
      });
  if (!rest.is_object()) throw std::runtime_error(file.string() + ": expected an object of frames' pixel counts");
}

ReportInputs load(const StageContext& context) {
  ReportInputs in;
  in.job_file = context.job_file;
  in.recording = shared_recording(context.need("source"));
  in.poses = shared_poses(context.need("poses"));
  const Artifact& labels = context.need("propagate").artifact;
  in.labels_summary = nlohmann::json::parse(read_file(labels.path("summary.json")));
  // The report's page is published at REPORT_ID/index.html, the overlays at LABELS_ID/SENSOR/overlay/.
  in.labels = &labels;
  in.labels_folder = "../" + context.need("propagate").stage_id + "/";
  in.frames.reserve(in.recording->observations.size());  // 10,000 frames: not grown by doubling
  for (size_t i = 0; i < in.recording->observations.size(); ++i) {
    const Observation& o = in.recording->observations[i];
    ReportFrame f;
    f.observation = &o;
    if (i < in.poses->size()) {
      f.pose = &(*in.poses)[i];
      f.pose_valid = f.pose->valid;
      if (f.pose->quality.consistency) f.consistency = f.pose->quality.consistency->fraction;
    }
    f.overlay = labels.files.place(overlay_file(o.sensor, o.id));
    in.frames.push_back(f);
  }
  read_frame_pixels(labels.path("frame_pixels.json"), in.frames);
  in.label_map = label_map_from_json(nlohmann::json::parse(read_file(labels.path("labels.json"))));
  if (const StageInput* annotations = context.input("annotations")) in.boxes = load_boxes(*annotations);
  if (const StageInput* scene = context.input("reconstruct")) {
    const fs::path points = scene->artifact.path("scene_points.bin");
    const std::optional<ListedFile> points_file = scene->artifact.file("scene_points.bin");
    const std::string digest = points_file ? points_file->sha256.hex() : "";
    const std::string points_name = context.kept_name("scene points");
    const auto decoded = made_once<ScenePoints>([points, digest, points_name] {
      return remembered_or_made<ScenePoints>(
          points_name, digest, [&] { return decode_scene_points(read_file(points), points.string()); },
          [](const ScenePoints& p) { return p.cloud.size() * sizeof(p.cloud[0]); });
    });
    in.scene = ReportScene{
        decoded, decode_scene_voxel_size(read_file_head(points, kScenePointsHeaderBytes), points.string()), digest,
        annotation_frame_from_json(nlohmann::json::parse(read_file(scene->artifact.path("annotation_frame.json"))))
            .T_world_annotation,
        keeping_memory() && !digest.empty() ? made_once<PointsByX>([decoded, digest, points_name] {
          return remembered_or_made<PointsByX>(
              points_name + " by x", digest, [&] { return points_by_x(decoded()->cloud); },
              [](const PointsByX& p) { return p.by_x.size() * sizeof(uint32_t); });
        })
                                            : nullptr};
  }
  in.memo = context.memo;
  return in;
}

nlohmann::json save(const ReportResult& result, const StageContext& context, ArtifactWriter& out) {
  const std::string folder = context.stage.id + "/";
  out.write("index.html", result.html);
  out.publish("index.html", folder + "index.html", "report");
  // Written in parallel (each of its own name), published in the page's order.
  parallel_for(result.pictures.size(),
               [&](size_t i) { out.write(result.pictures[i].first, result.pictures[i].second); });
  for (const auto& [file, bytes] : result.pictures) out.publish(file, folder + file, "report_picture");
  return nlohmann::json::object();
}

}  // namespace

StageKind report_kind() {
  // 5: class legend, per-frame plot, worst frames, SVG trajectory, tiles linked to the overlays;
  // 6: boxes drawn over the pictures by the page (SVG), not into them; 8: pictures' PNG with the "up" filter
  StageKind kind =
      make_stage_kind({"report", params(), {"source", "poses", "propagate"}, {"reconstruct", "annotations"}, nullptr},
                      8, nullptr, typed_stage(params(), load, run_report, save));
  kind.looks_up = {{"source", recording_lookup}, {"propagate", looked_up_in_labels}};
  return kind;
}

}  // namespace olt
