#include "report_boxes.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <set>
#include <string_view>
#include <vector>

#include "olt/core/image.h"
#include "olt/core/parallel.h"
#include "olt/core/text.h"
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

std::string hex_colour(const std::array<uint8_t, 3>& rgb) {
  char text[8];
  std::snprintf(text, sizeof(text), "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return text;
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
Eigen::Vector3d vector_from_json(const nlohmann::json& v) {
  return {v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>()};
}

// The scene in a layout, PNG; remembered by what it is drawn from (no box is: see the header).
std::string picture(const ReportInputs& in, const PreviewLayout& layout, const PreviewStyle& style) {
  const auto draw = [&] {
    const std::shared_ptr<const PointsByX> by_x = in.scene->points_by_x ? in.scene->points_by_x() : nullptr;
    return encode_picture_png(render_preview(in.scene->points()->cloud, layout, style, by_x.get()));
  };
  if (in.scene->points_digest.empty()) return draw();
  const nlohmann::json record = {{"picture", 3},
                                 {"scene", in.scene->points_digest},
                                 {"region", {vector_json(layout.region.lo), vector_json(layout.region.hi)}},
                                 {"canvas", {layout.canvas.width, layout.canvas.height}},
                                 {"grid_step_m", layout.grid_step_m},
                                 {"style", {style.point_size_m, style.axes, style.title}}};
  return in.memo(record, draw);
}

// The scene's extent without its stray points, remembered in the cache by the points' digest and the
// pad (the record's version names scene_region's way of finding it: bump it where that changes), so
// a run whose pictures are all in the cache decodes no point. The numbers as JSON writes them, which
// read back the same doubles; one that is not finite (JSON's null) is found again from the points.
Region scene_region_of(const ReportInputs& in) {
  const auto find = [&] { return scene_region(in.scene->points()->cloud, kScenePicturePadM); };
  const std::string& digest = in.scene->points_digest;
  if (digest.empty()) return find();
  const nlohmann::json record = {{"scene_region", 1}, {"scene", digest}, {"pad_m", kScenePicturePadM}};
  const nlohmann::json region = nlohmann::json::parse(in.memo(record, [&] {
    const Region r = find();
    return nlohmann::json{vector_json(r.lo), vector_json(r.hi)}.dump();
  }));
  const auto numbers = [](const nlohmann::json& v) {
    return v.is_array() && v.size() == 3 &&
           std::all_of(v.begin(), v.end(), [](const auto& x) { return x.is_number(); });
  };
  if (!region.is_array() || region.size() != 2 || !numbers(region[0]) || !numbers(region[1])) return find();
  return {vector_from_json(region[0]), vector_from_json(region[1])};
}

// A coordinate in an SVG path: pixels to a tenth.
std::string coordinate(double v) {
  char text[64];  // to_chars: printf's "%.1f" without its locale and formatting machinery
  const auto [end, error] = std::to_chars(text, text + sizeof(text), v, std::chars_format::fixed, 1);
  return error == std::errc() ? std::string(text, end) : format_text("%.1f", v);  // beyond 10^60: printf
}

// The 12 edges as an SVG path, each drawn once: a view along a box's axis sees its edges in pairs
// on top of each other, and the edges along that axis as points (left out). Each corner is written
// once: a TUM report draws up to a thousand outlines, and formatting 48 numbers and a set of
// strings for each was nearly a third of the report after a one-box edit.
std::string edges_path(const BoxOutline& outline) {
  std::array<std::string, 8> corner_text;
  for (size_t k = 0; k < corner_text.size(); ++k)
    corner_text[k] = coordinate(outline.corners[k].x()) + " " + coordinate(outline.corners[k].y());
  std::vector<std::pair<std::string_view, std::string_view>> drawn;  // an edge either way is the same
  std::string path;
  for (const auto& [a, b] : kBoxEdges) {
    const std::string_view from = corner_text[static_cast<size_t>(a)], to = corner_text[static_cast<size_t>(b)];
    const auto edge = from < to ? std::pair(from, to) : std::pair(to, from);
    if (from == to || std::find(drawn.begin(), drawn.end(), edge) != drawn.end()) continue;
    drawn.push_back(edge);
    path.append("M").append(from).append("L").append(to);
  }
  return path;
}

// The boxes that show in a layout, drawn over its picture: per view, clipped to its plot, each box's
// edges (titled with its id) and its name, in its class's colour. `id` names the clip paths (unique
// in the page).
std::string outlines_svg(const std::vector<PreviewBox>& boxes, const PreviewLayout& layout, const std::string& id) {
  const std::string width = std::to_string(layout.canvas.width), height = std::to_string(layout.canvas.height);
  std::string svg = "<svg viewBox=\"0 0 " + width + " " + height + "\" font-family=\"sans-serif\" font-size=\"" +
                    coordinate(name_font_px(layout)) + "\">";
  std::vector<size_t> shown;
  for (size_t k = 0; k < boxes.size(); ++k)
    if (box_shows(boxes[k], layout)) shown.push_back(k);
  for (size_t v = 0; v < layout.views.size(); ++v) {
    const OrthoView& view = layout.views[v];
    const std::string clip = id + "-" + std::to_string(v);
    svg += "<clipPath id=\"" + clip + "\"><rect x=\"" + std::to_string(view.plot.x) + "\" y=\"" +
           std::to_string(view.plot.y) + "\" width=\"" + std::to_string(view.plot.width) + "\" height=\"" +
           std::to_string(view.plot.height) + "\"/></clipPath><g clip-path=\"url(#" + clip + ")\">";
    for (size_t k : shown) {
      const BoxOutline outline = box_outline(view, boxes[k]);
      const std::string colour = hex_colour(boxes[k].rgb), name = html_escape(boxes[k].text);
      svg += "<path d=\"" + edges_path(outline) + "\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" +
             std::to_string(boxes[k].thickness_px) + "\"><title>" + name + "</title></path>";
      if (!name.empty())
        svg += "<text x=\"" + coordinate(outline.text_at.x()) + "\" y=\"" + coordinate(outline.text_at.y()) +
               "\" fill=\"" + colour +
               "\" stroke=\"#000\" stroke-width=\"2.5\" stroke-linejoin=\"round\" paint-order=\"stroke\">" + name +
               "</text>";
    }
    svg += "</g>";
  }
  return svg + "</svg>";
}

// A picture with the boxes drawn over it, in a figure.
std::string figure(const std::string& file, const std::string& outlines, int width_px, const std::string& caption) {
  return "<figure><div class=\"picture\"><img src=\"" + file + "\" width=\"" + std::to_string(width_px) + "\">" +
         outlines + "</div><figcaption>" + caption + "</figcaption></figure>\n";
}

}  // namespace

BoxPictures draw_box_pictures(const ReportInputs& in, const ReportConfig& c) {
  BoxPictures out;
  out.html = "<h2>Boxes</h2>\n";
  if (!in.scene) {
    out.html += "<p>No scene to draw the boxes in (no reconstruct stage upstream).</p>\n";
    return out;
  }
  const std::vector<PreviewBox> boxes = preview_boxes(in);
  Region region = scene_region_of(in);
  for (const auto& box : boxes)
    for (const auto& corner : box.corners) {
      region.lo = region.lo.cwiseMin(corner);
      region.hi = region.hi.cwiseMax(corner);
    }
  // Every picture and its outlines drawn in parallel (the scene's last), then listed in the boxes' order.
  std::set<std::string> used;
  std::vector<std::string> files;
  for (const Box& box : in.boxes) files.push_back(picture_file(box.id, used));
  std::vector<PreviewLayout> layouts;
  for (const auto& box : boxes) layouts.push_back(preview_layout(crop_region(box), c.box_picture_px, 40));
  layouts.push_back(preview_layout(region, c.scene_picture_px));
  std::vector<std::string> png(layouts.size()), outlines(boxes.size());
  parallel_for(png.size(), [&](size_t i) {
    const bool scene_picture = i == boxes.size();
    const PreviewStyle style{in.scene->voxel_size_m, scene_picture || holds_origin(layouts[i].region), ""};
    png[i] = picture(in, layouts[i], style);
    if (scene_picture) return;
    std::vector<PreviewBox> drawn = boxes;  // the others thinner
    for (size_t j = 0; j < drawn.size(); ++j) drawn[j].thickness_px = j == i ? 2 : 1;
    outlines[i] = outlines_svg(drawn, layouts[i], "box" + std::to_string(i));
  });
  out.files.emplace_back("scene_boxes.png", std::move(png.back()));
  out.html += figure("scene_boxes.png", outlines_svg(boxes, layouts.back(), "scene"), 2 * c.scene_picture_px,
                     "the levelled scene (the annotation frame, where boxes are drawn) with every box in its class's "
                     "colour, named by its id");
  if (boxes.empty()) {
    out.html += "<p>No boxes.</p>\n";
    return out;
  }
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& box = in.boxes[i];
    out.files.emplace_back(files[i], std::move(png[i]));
    out.html += figure(files[i], outlines[i], 2 * c.box_picture_px,
                       "<b>" + html_escape(box.id) + "</b>: " + html_escape(box.label) + " (instance " +
                           html_escape(box.instance) + ")");
  }
  return out;
}

}  // namespace olt
