#include "report_boxes.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "olt/core/image.h"
#include "olt/core/parallel.h"
#include "olt/reconstruct/preview.h"

namespace olt {

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string url_path(const std::string& path) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '.' || c == '-' || c == '_' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

namespace {

// "boxes/ID.png" with characters that are not safe in a file name (or a URL) replaced by '_'; a
// suffix where two ids become one name.
std::string picture_file(const std::string& id, std::set<std::string>& used) {
  std::string name;
  for (char c : id) name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  if (name.empty()) name = "_";
  std::string file = "boxes/" + name + ".png";
  for (int n = 2; !used.insert(file).second; ++n) file = "boxes/" + name + "-" + std::to_string(n) + ".png";
  return file;
}

// The boxes in the annotation frame, in their class's colour, named by id.
std::vector<PreviewBox> preview_boxes(const ReportInputs& in) {
  const Pose T_annotation_world = in.scene->T_world_annotation.inverse();
  std::vector<PreviewBox> out;
  for (const Box& box : in.boxes) {
    PreviewBox p;
    const auto corners = box_corners(box);
    for (size_t i = 0; i < 8; ++i) p.corners[i] = T_annotation_world * corners[i];
    for (const auto& c : in.label_map.classes)
      if (c.name == box.label) p.rgb = c.color;
    p.text = box.id;
    out.push_back(p);
  }
  return out;
}

// Around a box: its extent widened by a third of its largest side, and 0.2 m at least.
Region crop_region(const PreviewBox& box) {
  Region r{box.corners[0], box.corners[0]};
  for (const auto& c : box.corners) {
    r.lo = r.lo.cwiseMin(c);
    r.hi = r.hi.cwiseMax(c);
  }
  const double pad = std::max(0.2, (r.hi - r.lo).maxCoeff() / 3);
  r.lo.array() -= pad;
  r.hi.array() += pad;
  return r;
}

bool holds_origin(const Region& r) { return (r.lo.array() <= 0).all() && (r.hi.array() >= 0).all(); }

nlohmann::json vector_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// The scene drawn with the boxes that show in it (the others would not change a pixel), PNG;
// remembered by everything it is drawn from, so an edit redraws the pictures the edited box shows in.
std::string picture(const ReportInputs& in, const std::vector<PreviewBox>& boxes, const PreviewLayout& layout,
                    const PreviewStyle& style) {
  std::vector<PreviewBox> shown;
  nlohmann::json drawn = nlohmann::json::array();
  for (const auto& box : boxes) {
    if (!box_shows(box, layout)) continue;
    shown.push_back(box);
    nlohmann::json corners = nlohmann::json::array();
    for (const auto& corner : box.corners) corners.push_back(vector_json(corner));
    drawn.push_back({{"corners", corners}, {"rgb", box.rgb}, {"text", box.text}, {"thickness_px", box.thickness_px}});
  }
  const auto draw = [&] { return encode_png(render_preview(in.scene->points.cloud, shown, layout, style)); };
  if (in.scene->points_digest.empty()) return draw();
  const nlohmann::json record = {{"picture", 1},
                                 {"scene", in.scene->points_digest},
                                 {"region", {vector_json(layout.region.lo), vector_json(layout.region.hi)}},
                                 {"canvas", {layout.canvas.width, layout.canvas.height}},
                                 {"grid_step_m", layout.grid_step_m},
                                 {"style", {style.point_size_m, style.axes, style.title}},
                                 {"boxes", drawn}};
  return in.memo(record, draw);
}

}  // namespace

BoxPictures draw_box_pictures(const ReportInputs& in, const ReportConfig& c) {
  BoxPictures out;
  out.html = "<h2>Boxes</h2>\n";
  if (!in.scene) {
    out.html += "<p>No scene to draw the boxes in (no reconstruct stage upstream).</p>\n";
    return out;
  }
  const ScenePoints& scene = in.scene->points;
  const std::vector<PreviewBox> boxes = preview_boxes(in);
  Region region = scene_region(scene.cloud, 0.25);
  for (const auto& box : boxes)
    for (const auto& corner : box.corners) {
      region.lo = region.lo.cwiseMin(corner);
      region.hi = region.hi.cwiseMax(corner);
    }
  // Every picture drawn in parallel (the scene's last), then listed in the boxes' order.
  std::set<std::string> used;
  std::vector<std::string> files;
  for (const Box& box : in.boxes) files.push_back(picture_file(box.id, used));
  std::vector<std::string> png(boxes.size() + 1);
  parallel_for(png.size(), [&](size_t i) {
    if (i == boxes.size()) {
      png[i] = picture(in, boxes, preview_layout(region, c.scene_picture_px), {scene.voxel_size_m, true, ""});
      return;
    }
    const Region crop = crop_region(boxes[i]);
    std::vector<PreviewBox> drawn = boxes;  // the others thinner
    for (size_t j = 0; j < drawn.size(); ++j) drawn[j].thickness_px = j == i ? 2 : 1;
    png[i] =
        picture(in, drawn, preview_layout(crop, c.box_picture_px, 40), {scene.voxel_size_m, holds_origin(crop), ""});
  });
  out.files.emplace_back("scene_boxes.png", std::move(png.back()));
  out.html += "<figure><img src=\"scene_boxes.png\" width=\"" + std::to_string(2 * c.scene_picture_px) +
              "\"><figcaption>the levelled scene (the annotation frame, where boxes are drawn) with every box "
              "in its class's colour, named by its id</figcaption></figure>\n";
  if (boxes.empty()) {
    out.html += "<p>No boxes.</p>\n";
    return out;
  }
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& box = in.boxes[i];
    out.files.emplace_back(files[i], std::move(png[i]));
    out.html += "<figure><img src=\"" + files[i] + "\" width=\"" + std::to_string(2 * c.box_picture_px) +
                "\"><figcaption><b>" + html_escape(box.id) + "</b>: " + html_escape(box.label) + " (instance " +
                html_escape(box.instance) + ")</figcaption></figure>\n";
  }
  return out;
}

}  // namespace olt
