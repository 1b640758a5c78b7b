// `report`: one HTML page and its pictures, for a person to see in ten seconds whether the labels
// are right: the trajectory from above, the levelled scene with every box and a picture around each
// box (when a reconstruct stage is upstream; report_boxes.h), a contact sheet of overlays, per-class pixel and frame
// counts, the flagged observations, and (registered poses) each observation's consistency with the scene.
#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "olt/core/image.h"
#include "olt/eval/trajectory_error.h"
#include "olt/reconstruct/level.h"
#include "olt/stages/artifacts.h"
#include "olt/stages/kinds.h"
#include "olt/stages/report.h"
#include "olt/stages/typed_stage.h"
#include "report_boxes.h"

namespace olt {
namespace {

std::shared_ptr<const Params<ReportConfig>> params() {
  static auto p = [] {
    auto t = std::make_shared<Params<ReportConfig>>();
    t->integer("contact_sheet_frames", &ReportConfig::contact_sheet_frames, between(1, 400),
               "overlays on the contact sheet, evenly spread")
        .integer("tile_width_px", &ReportConfig::tile_width_px, between(40, 2000), "width of one overlay on the sheet")
        .integer("scene_picture_px", &ReportConfig::scene_picture_px, between(100, 4000),
                 "height of the scene with its boxes, pixels")
        .integer("box_picture_px", &ReportConfig::box_picture_px, between(100, 2000),
                 "height of each box's picture, pixels");
    return t;
  }();
  return p;
}

// Every k-th overlay the propagate stage wrote, tiled with its observation id under it.
cv::Mat contact_sheet(const std::vector<std::pair<std::string, fs::path>>& overlays, const ReportConfig& c) {
  if (overlays.empty()) return {};
  const size_t count = std::min(overlays.size(), static_cast<size_t>(c.contact_sheet_frames));
  const int columns = std::min<int>(6, static_cast<int>(count));
  const int rows = static_cast<int>((count + columns - 1) / columns);
  cv::Mat sheet;
  int tile_height = 0;
  for (size_t i = 0; i < count; ++i) {
    const auto& [name, path] = overlays[i * overlays.size() / count];
    cv::Mat image = read_color(path), tile;
    const double scale = static_cast<double>(c.tile_width_px) / image.cols;
    cv::resize(image, tile, cv::Size(), scale, scale, cv::INTER_AREA);
    if (sheet.empty()) {
      tile_height = tile.rows + 18;
      sheet = cv::Mat(rows * tile_height, columns * c.tile_width_px, CV_8UC3, cv::Scalar(255, 255, 255));
    }
    const int x = static_cast<int>(i % columns) * c.tile_width_px, y = static_cast<int>(i / columns) * tile_height;
    tile.copyTo(sheet(cv::Rect(x, y, tile.cols, std::min(tile.rows, tile_height - 18))));
    cv::putText(sheet, name, {x + 4, y + tile_height - 5}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {60, 60, 60}, 1, cv::LINE_AA);
  }
  return sheet;
}

// Per observation, in time order, the fraction of its depth points on the scene the poses make
// (poses' quality.consistency, registration with keyframes): a line a person reads at a glance,
// flagged observations in red. Empty when no pose carries the score.
cv::Mat consistency_plot(const std::vector<ObservationPose>& poses) {
  std::vector<std::pair<double, bool>> scores;  // fraction, valid
  for (const auto& p : poses)
    if (p.quality.consistency) scores.emplace_back(p.quality.consistency->fraction, p.valid);
  if (scores.empty()) return {};
  const int width = 600, height = 220, left = 40, right = 10, top = 20, bottom = 30;
  cv::Mat plot(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  auto at = [&](size_t i, double fraction) {
    const double x = scores.size() > 1 ? static_cast<double>(i) / (scores.size() - 1) : 0.5;
    return cv::Point(left + static_cast<int>(x * (width - left - right)),
                     top + static_cast<int>((1 - fraction) * (height - top - bottom)));
  };
  for (double level : {0.0, 0.5, 1.0}) {
    cv::line(plot, at(0, level), {width - right, at(0, level).y}, {220, 220, 220}, 1);
    char text[8];
    std::snprintf(text, sizeof(text), "%.1f", level);
    cv::putText(plot, text, {4, at(0, level).y + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {90, 90, 90}, 1, cv::LINE_AA);
  }
  for (size_t i = 1; i < scores.size(); ++i)
    cv::line(plot, at(i - 1, scores[i - 1].first), at(i, scores[i].first), {170, 120, 40}, 1, cv::LINE_AA);
  for (size_t i = 0; i < scores.size(); ++i)
    if (!scores[i].second) cv::circle(plot, at(i, scores[i].first), 4, {40, 40, 220}, -1, cv::LINE_AA);
  cv::putText(plot, "observations in time order (red: flagged)", {left, height - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
              {90, 90, 90}, 1, cv::LINE_AA);
  return plot;
}

// The pictures drawn and shown (boxes and sheet last, under their own headings), and the figures' HTML.
std::string draw_pictures(const ReportInputs& in, const ReportConfig& c, ReportResult& result) {
  std::string figures;
  auto show = [&](const std::string& file, std::string bytes, const std::string& figure) {
    result.pictures.emplace_back(file, std::move(bytes));
    figures += figure;
  };
  Trajectory path;
  for (const auto& p : in.poses)
    if (p.valid) path.push_back({p.timestamp, p.T_world_sensor});
  if (!path.empty())
    show("trajectory.png", encode_png(plot_trajectories(path, {}, Pose::Identity(), 500, "sensor positions")),
         "<figure><img src=\"trajectory.png\" width=\"400\"><figcaption>the sensor's path from above "
         "(world x right, y up)</figcaption></figure>\n");
  if (const cv::Mat plot = consistency_plot(in.poses); !plot.empty())
    show("consistency.png", encode_png(plot),
         "<figure><img src=\"consistency.png\" width=\"600\"><figcaption>per observation: the fraction of its "
         "depth points within a few centimetres of the scene (1 = its pose agrees with the scene)</figcaption>"
         "</figure>\n");
  BoxPictures boxes = draw_box_pictures(in, c);
  for (auto& [file, bytes] : boxes.files) result.pictures.emplace_back(file, std::move(bytes));
  figures += boxes.html;
  const cv::Mat sheet = contact_sheet(in.overlays, c);
  if (sheet.empty()) return figures + "<p>No overlays (propagate's <code>overlays</code> is off).</p>\n";
  show("contact_sheet.jpg", encode_jpeg(sheet),
       "<h2>Overlays</h2>\n<img src=\"contact_sheet.jpg\" style=\"max-width:100%\">\n");
  return figures;
}

// The tables' HTML: the boxes' warnings, classes and instances (pixels, frames), flagged observations.
std::string tables(const ReportInputs& in) {
  const auto row = [](const std::vector<std::string>& cells) {
    std::string html = "<tr>";
    for (const auto& cell : cells) html += "<td>" + html_escape(cell) + "</td>";
    return html + "</tr>\n";
  };
  const nlohmann::json& summary = in.labels_summary;
  // Named: a range over a temporary's items() would dangle.
  const nlohmann::json listed = summary.value("warnings", nlohmann::json::array()),
                       class_counts = summary.value("classes", nlohmann::json::object()),
                       instance_counts = summary.value("instances", nlohmann::json::object());
  std::string warnings;
  for (const auto& w : listed) warnings += "<li>" + html_escape(w.get<std::string>()) + "</li>\n";
  std::string classes;
  for (const auto& [name, counts] : class_counts.items())
    classes += row({name, std::to_string(counts.value("pixels", 0)), std::to_string(counts.value("frames", 0))});
  std::string instances;
  for (const auto& [name, counts] : instance_counts.items()) {
    std::string boxes;
    for (const auto& b : counts.value("boxes", nlohmann::json::array()))
      boxes += (boxes.empty() ? "" : " ") + b.get<std::string>();
    instances += row({name, counts.value("label", ""), boxes, std::to_string(counts.value("pixels", 0)),
                      std::to_string(counts.value("frames", 0))});
  }
  std::string flagged;
  for (const auto& p : in.poses)
    if (!p.valid) flagged += "<li>" + html_escape(p.sensor + " " + p.observation + ": " + p.flag) + "</li>\n";
  return "<h2>Boxes to check</h2>\n<ul>\n" + (warnings.empty() ? "<li>none</li>\n" : warnings) +
         "</ul>\n<h2>Classes</h2>\n<table><tr><th>class</th><th>pixels</th><th>frames</th></tr>\n" + classes +
         "</table>\n<h2>Instances</h2>\n<table><tr><th>instance</th><th>class</th><th>boxes</th><th>pixels</th>"
         "<th>frames</th></tr>\n" +
         instances + "</table>\n<h2>Flagged observations</h2>\n<ul>\n" +
         (flagged.empty() ? "<li>none</li>\n" : flagged) + "</ul>\n";
}

}  // namespace

ReportResult run_report(const ReportInputs& in, const ReportConfig& c) {
  const nlohmann::json& summary = in.labels_summary;
  ReportResult result;
  const std::string figures = draw_pictures(in, c, result);

  result.html =
      "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>OLT report: " +
      html_escape(in.job_file.stem().string()) +
      "</title>\n<style>body{font-family:sans-serif;margin:2em}figure{display:inline-block;margin:0 1em 1em 0}"
      "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}"
      "td:first-child{text-align:left}</style></head><body>\n<h1>" +
      html_escape(in.job_file.filename().string()) + "</h1>\n<p>" +
      std::to_string(summary.value("observations_labeled", 0)) + " observations labeled, " +
      std::to_string(summary.value("observations_skipped", 0)) + " skipped (flagged poses); " +
      std::to_string(summary.value("ambiguous_pixels", 0)) + " pixels inside more than one box.</p>\n" + figures +
      tables(in) + "</body></html>\n";
  return result;
}

namespace {

ReportInputs load(const StageContext& context) {
  ReportInputs in;
  in.job_file = context.job_file;
  in.recording = load_recording(context.need("source"));
  in.poses = load_poses(context.need("poses"));
  const Artifact& labels = context.need("propagate").artifact;
  in.labels_summary = nlohmann::json::parse(read_file(labels.dir / "summary.json"));
  for (const auto& o : in.recording.observations) {
    const std::string file = o.sensor + "/overlay/" + o.id + ".jpg";
    if (labels.file(file)) in.overlays.emplace_back(o.sensor + " " + o.id, labels.dir / file);
  }
  in.label_map = label_map_from_json(nlohmann::json::parse(read_file(labels.dir / "labels.json")));
  if (const StageInput* annotations = context.input("annotations")) in.boxes = load_boxes(*annotations);
  if (const StageInput* scene = context.input("reconstruct")) {
    const fs::path points = scene->artifact.dir / "scene_points.bin";
    in.scene = ReportScene{
        decode_scene_points(read_file(points), points.string()),
        annotation_frame_from_json(nlohmann::json::parse(read_file(scene->artifact.dir / "annotation_frame.json")))
            .T_world_annotation};
  }
  return in;
}

nlohmann::json save(const ReportResult& result, const StageContext& context, ArtifactWriter& out) {
  const std::string folder = context.stage.id + "/";
  out.write("index.html", result.html);
  out.publish("index.html", folder + "index.html", "report");
  for (const auto& [file, bytes] : result.pictures) {
    out.write(file, bytes);
    out.publish(file, folder + file, "report_picture");
  }
  return nlohmann::json::object();
}

}  // namespace

StageKind report_kind() {
  // 4: the scene with its boxes and a picture per box; the boxes' warnings and the instances' table
  return make_stage_kind(
      {"report", params(), {"source", "poses", "propagate"}, {"reconstruct", "annotations"}, nullptr}, 4, nullptr,
      typed_stage(params(), load, run_report, save));
}

}  // namespace olt
