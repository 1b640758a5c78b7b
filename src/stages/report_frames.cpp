#include "report_frames.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "report_boxes.h"

namespace olt {
namespace {

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", v);
  return text;
}

std::string pct(double fraction) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f%%", 100 * fraction);
  return text;
}

// A frame's name and figures, for a point's tooltip.
std::string frame_title(const ReportFrame& f, size_t index) {
  std::string t = "#" + std::to_string(index) + " " + f.name();
  if (f.labeled) t += ": " + pct(f.labeled_fraction()) + " of depth pixels labeled";
  if (f.consistency) t += ", consistency " + pct(*f.consistency);
  if (!f.pose_valid) t += " (flagged: " + f.flag() + ")";
  return html_escape(t);
}

std::string linked(const std::string& link, const std::string& inner) {
  return link.empty() ? inner : "<a href=\"" + html_escape(link) + "\">" + inner + "</a>";
}

// Beyond this many frames the line alone is drawn (the flagged and the worst still marked): a point
// per frame would make the page megabytes.
constexpr size_t kPointsUpTo = 2000;

}  // namespace

double share_against_neighbours(const std::vector<ReportFrame>& frames, size_t i, size_t radius) {
  std::vector<double> around;
  const size_t from = i > radius ? i - radius : 0, to = std::min(frames.size(), i + radius + 1);
  for (size_t k = from; k < to; ++k)
    if (k != i && frames[k].labeled && frames[k].observation->sensor == frames[i].observation->sensor)
      around.push_back(frames[k].labeled_fraction());
  if (around.empty()) return 1;
  std::nth_element(around.begin(), around.begin() + around.size() / 2, around.end());
  const double median = around[around.size() / 2];
  return median > 0 ? frames[i].labeled_fraction() / median : 1;
}

std::vector<size_t> worst_frames(const std::vector<ReportFrame>& frames, int count) {
  std::vector<std::pair<double, size_t>> ranked;
  for (size_t i = 0; i < frames.size(); ++i)
    if (frames[i].labeled)
      if (const double share = share_against_neighbours(frames, i); share < 0.9) ranked.emplace_back(share, i);
  std::sort(ranked.begin(), ranked.end());
  std::vector<size_t> out;
  for (size_t k = 0; k < ranked.size() && static_cast<int>(k) < count; ++k) out.push_back(ranked[k].second);
  return out;
}

std::string frames_plot_svg(const ReportInputs& in, const std::vector<size_t>& worst) {
  const std::vector<ReportFrame>& frames = in.frames;
  if (frames.empty()) return "";
  double top = 0.05;  // the y axis runs to the largest share, rounded up to 10%
  bool consistency = false;
  for (const auto& f : frames) {
    top = std::max(top, f.labeled_fraction());
    consistency |= f.consistency.has_value();
  }
  if (consistency) top = 1;
  top = std::min(1.0, std::ceil(top * 10) / 10);
  const double width = 820, height = 240, left = 48, right = 12, upper = 14, lower = 34;
  const auto x = [&](size_t i) {
    return left + (frames.size() > 1 ? double(i) / double(frames.size() - 1) : 0.5) * (width - left - right);
  };
  const auto y = [&](double v) { return upper + (1 - v / top) * (height - upper - lower); };
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width) + "\" height=\"" + num(height) +
                    "\" viewBox=\"0 0 " + num(width) + " " + num(height) +
                    "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  const double grid = top <= 0.5 ? 0.1 : 0.2;
  for (double v = 0; v <= top + 1e-9; v += grid) {
    svg += "<line x1=\"" + num(left) + "\" x2=\"" + num(width - right) + "\" y1=\"" + num(y(v)) + "\" y2=\"" +
           num(y(v)) + "\" stroke=\"#ddd\"/><text x=\"4\" y=\"" + num(y(v) + 4) + "\" fill=\"#555\">" +
           pct(v).substr(0, pct(v).size() - 3) + "%</text>\n";
  }
  const auto polyline = [&](auto value, const char* colour) {
    std::string points;
    for (size_t i = 0; i < frames.size(); ++i)
      if (const auto v = value(frames[i])) points += num(x(i)) + "," + num(y(*v)) + " ";
    return points.empty() ? std::string()
                          : "<polyline fill=\"none\" stroke=\"" + std::string(colour) +
                                "\" stroke-width=\"1.5\" points=\"" + points + "\"/>\n";
  };
  svg += polyline([](const ReportFrame& f) { return f.labeled ? std::optional(f.labeled_fraction()) : std::nullopt; },
                  "#2a6fb0");
  svg += polyline([](const ReportFrame& f) { return f.consistency; }, "#e08a1e");
  for (size_t i = 0; i < frames.size(); ++i) {
    const ReportFrame& f = frames[i];
    const bool bad = std::find(worst.begin(), worst.end(), i) != worst.end();
    if (f.pose_valid && !bad) {
      if (f.labeled && frames.size() <= kPointsUpTo)
        svg += linked(overlay_link(in, f), "<circle cx=\"" + num(x(i)) + "\" cy=\"" + num(y(f.labeled_fraction())) +
                                               "\" r=\"2.5\" fill=\"#2a6fb0\"><title>" + frame_title(f, i) +
                                               "</title></circle>") +
               "\n";
      continue;
    }
    const double at = f.labeled ? f.labeled_fraction() : 0;
    const std::string circle =
        std::string("<circle cx=\"") + num(x(i)) + "\" cy=\"" + num(y(at)) + "\" r=\"" +
        (bad ? "6\" fill=\"none\" stroke=\"#e0301e\" stroke-width=\"2\"" : "4\" fill=\"#e0301e\"");
    // Beyond the points' limit a flagged frame is a bare mark (many may be flagged); the worst are few.
    svg += (frames.size() <= kPointsUpTo || bad
                ? linked(overlay_link(in, f), circle + "><title>" + frame_title(f, i) + "</title></circle>")
                : circle + "/>") +
           "\n";
  }
  svg += "<text x=\"" + num(left) + "\" y=\"" + num(height - 8) +
         "\" fill=\"#555\">frames in the recording's order: <tspan fill=\"#2a6fb0\">labeled share of depth "
         "pixels</tspan>" +
         (consistency ? ", <tspan fill=\"#e08a1e\">pose consistency</tspan>" : "") +
         ", <tspan fill=\"#e0301e\">flagged (dot) and worst (ring)</tspan></text>\n</svg>\n";
  return svg;
}

std::string trajectory_svg(const std::vector<ObservationPose>& poses) {
  std::vector<size_t> valid;
  for (size_t i = 0; i < poses.size(); ++i)
    if (poses[i].valid) valid.push_back(i);
  if (valid.empty()) return "";
  double x0 = std::numeric_limits<double>::max(), y0 = x0, x1 = -x0, y1 = -x0;
  for (size_t i : valid) {
    const Eigen::Vector3d p = poses[i].T_world_sensor.translation();
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  }
  const double extent = std::max({x1 - x0, y1 - y0, 0.5}) * 1.15, cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  const double size = 420, scale = size / extent;
  const auto sx = [&](double v) { return size / 2 + (v - cx) * scale; };
  const auto sy = [&](double v) { return size / 2 - (v - cy) * scale; };
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(size) + "\" height=\"" + num(size + 20) +
                    "\" viewBox=\"0 0 " + num(size) + " " + num(size + 20) +
                    "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  double step = extent > 20 ? 5 : extent > 5 ? 1 : extent > 1 ? 0.5 : 0.1;  // grid, metres
  while (extent / step > 10) step *= 10;                                    // a pose far off: still about ten lines
  for (double k = std::ceil((cx - extent / 2) / step); k * step <= cx + extent / 2; ++k)
    svg += "<line x1=\"" + num(sx(k * step)) + "\" x2=\"" + num(sx(k * step)) + "\" y1=\"0\" y2=\"" + num(size) +
           "\" stroke=\"#eee\"/>\n";
  for (double k = std::ceil((cy - extent / 2) / step); k * step <= cy + extent / 2; ++k)
    svg += "<line x1=\"0\" x2=\"" + num(size) + "\" y1=\"" + num(sy(k * step)) + "\" y2=\"" + num(sy(k * step)) +
           "\" stroke=\"#eee\"/>\n";
  std::string points;
  for (size_t i : valid)
    points += num(sx(poses[i].T_world_sensor.translation().x())) + "," +
              num(sy(poses[i].T_world_sensor.translation().y())) + " ";
  svg += "<polyline fill=\"none\" stroke=\"#2a6fb0\" stroke-width=\"1.5\" points=\"" + points + "\"/>\n";
  const Eigen::Vector3d first = poses[valid.front()].T_world_sensor.translation();
  svg += "<circle cx=\"" + num(sx(first.x())) + "\" cy=\"" + num(sy(first.y())) +
         "\" r=\"4\" fill=\"#2a6fb0\"><title>start</title></circle>\n";
  std::map<std::string, std::vector<std::pair<double, size_t>>> by_sensor;  // valid poses by time
  for (size_t i : valid) by_sensor[poses[i].sensor].emplace_back(poses[i].timestamp, i);
  for (auto& [sensor, times] : by_sensor) std::sort(times.begin(), times.end());
  for (size_t i = 0; i < poses.size(); ++i) {
    const auto times = by_sensor.find(poses[i].sensor);
    if (poses[i].valid || times == by_sensor.end()) continue;  // drawn at the nearest valid pose of its sensor
    const auto& t = times->second;
    auto after = std::lower_bound(t.begin(), t.end(), std::make_pair(poses[i].timestamp, size_t{0}));
    if (after == t.end() ||
        (after != t.begin() && poses[i].timestamp - std::prev(after)->first < after->first - poses[i].timestamp))
      after = std::prev(after);
    const Eigen::Vector3d p = poses[after->second].T_world_sensor.translation();
    svg += "<circle cx=\"" + num(sx(p.x())) + "\" cy=\"" + num(sy(p.y())) + "\" r=\"4\" fill=\"#e0301e\"><title>" +
           html_escape(poses[i].sensor + " " + poses[i].observation + ": " + poses[i].flag) + "</title></circle>\n";
  }
  svg += "<line x1=\"10\" x2=\"" + num(10 + step * scale) + "\" y1=\"" + num(size + 12) + "\" y2=\"" + num(size + 12) +
         "\" stroke=\"#333\" stroke-width=\"2\"/><text x=\"" + num(16 + step * scale) + "\" y=\"" + num(size + 16) +
         "\" fill=\"#333\">" + num(step) + " m (grid)</text>\n</svg>\n";
  return svg;
}

}  // namespace olt
