// The report stage: one page with the pictures it names (the scene with its boxes, one picture per
// box, overlay tiles linked to the overlays), the class legend and counts, the per-frame plot; and
// the page as a real browser (headless Chromium) loads it: every image there, no console message.
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>  // flags only

#include "olt/core/image_codec.h"
#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

const char* kJob = R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: 8, width: 160, height: 120}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  scene: {kind: reconstruct, needs: [poses], params: {every: 4, preview_size_px: 100}}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations]}
  report: {kind: report, needs: [labels, scene], params: {contact_sheet_frames: 4, tile_width_px: 80}}
)";

std::string hex(const nlohmann::json& rgb) {
  char text[8];
  std::snprintf(text, sizeof(text), "#%02x%02x%02x", rgb[0].get<int>(), rgb[1].get<int>(), rgb[2].get<int>());
  return text;
}

}  // namespace

TEST_CASE(
    "report: class legend, instances, per-frame plot, trajectory, scene with boxes, box pictures and overlay tiles "
    "linked to the overlays") {
  TempDir dir;
  write_text(dir / "job.yaml", kJob);
  const auto run = run_olt("run " + (dir / "job.yaml").string());
  REQUIRE(run.exit_code == 0);
  const std::string html = read_text(dir / "out/report/index.html");
  CHECK_THAT(html, Catch::Contains("<title>OLT report: job</title>"));  // the job's name, no machine path
  CHECK_THAT(html, !Catch::Contains(dir.path().string()));
  CHECK_THAT(html, Catch::Contains("scene_boxes.png"));
  // Per frame: a point titled with the frame and linked to its overlay; the trajectory as SVG.
  CHECK_THAT(html, Catch::Contains("<a href=\"../labels/rgbd/overlay/000003.jpg\"><circle"));
  CHECK_THAT(html, Catch::Contains("<title>#3 rgbd 000003: "));
  CHECK_THAT(html, Catch::Contains("<h2>Trajectory</h2>\n<figure><svg"));
  // 4 tiles, evenly spread (frames 0, 2, 4, 6), 80 px wide, each linked to its full overlay.
  cv::Mat tile;
  std::string error;
  for (int frame : {0, 2, 4, 6}) {
    const std::string id = "00000" + std::to_string(frame), file = "tiles/" + std::to_string(frame) + ".jpg";
    INFO(file);
    CHECK_THAT(html, Catch::Contains("<a href=\"../labels/rgbd/overlay/" + id + ".jpg\"><img src=\"" + file + "\""));
    olt::image_codec().decode(read_text(dir / "out/report" / file), cv::IMREAD_COLOR, tile, error);
    REQUIRE(error.empty());
    CHECK(tile.size() == cv::Size(80, 60));
    CHECK(fs::exists(dir / "out/labels/rgbd/overlay" / (id + ".jpg")));
  }
  CHECK_FALSE(fs::exists(dir / "out/report/tiles/1.jpg"));
  CHECK_THAT(html, Catch::Contains("8 of 8 observations labeled; "));
  CHECK_THAT(html, Catch::Contains("<p>0 of 8 (0%): their poses are not trusted"));
  // The legend: every class with its id, colour swatch and colour, pixels and frames as labels.json has them.
  const auto manifest = nlohmann::json::parse(read_text(dir / "out/manifest.json"));
  const auto labels = nlohmann::json::parse(read_text(dir / "out/labels.json"));
  REQUIRE(labels["classes"].size() >= 3);
  for (const auto& c : labels["classes"]) {
    const std::string name = c["name"], colour = hex(c["color"]);
    const auto& counts = labels["instance_counts"];
    long pixels = 0;
    for (const auto& [instance, n] : counts.items())
      if (n["label"] == name) pixels += n["pixels"].get<long>();
    CHECK_THAT(html, Catch::Contains("<tr><td><span class=\"swatch\" style=\"background:" + colour + "\"></span>" +
                                     name + "</td><td>" + std::to_string(c["id"].get<int>()) + "</td><td>" + colour +
                                     "</td><td>" + std::to_string(pixels) + "</td>"));
  }
  // Every instance with its class, boxes and counts as labels.json has them; no box to check.
  for (const auto& [name, counts] : labels["instance_counts"].items())
    CHECK_THAT(html, Catch::Contains("<tr><td>" + name + "</td><td>" + counts["label"].get<std::string>() +
                                     "</td><td>" + counts["boxes"][0].get<std::string>() + "</td><td>" +
                                     std::to_string(counts["pixels"].get<long>()) + "</td>"));
  CHECK_THAT(html, Catch::Contains("<h2>Boxes to check</h2>\n<ul>\n<li>none</li>"));
  int reports = 0;
  for (const auto& f : manifest["files"]) reports += f["kind"] == "report";
  CHECK(reports == 1);

  // One picture per box, named by its id, captioned with id, label and instance, each published.
  const auto boxes = nlohmann::json::parse(read_text(dir / "out/annotations/boxes.json"))["boxes"];
  REQUIRE(boxes.size() >= 3);
  size_t figures = 0;
  for (size_t at = html.find("src=\"boxes/"); at != std::string::npos; at = html.find("src=\"boxes/", at + 1))
    ++figures;
  CHECK(figures == boxes.size());
  for (const auto& box : boxes) {
    const std::string id = box["id"], file = "boxes/" + id + ".png";
    INFO("box " << id);
    CHECK_THAT(html, Catch::Contains("<img src=\"" + file + "\"") &&
                         Catch::Contains("<b>" + id + "</b>: " + box["label"].get<std::string>() + " (instance " +
                                         box.value("instance", id) + ")"));
    cv::Mat picture;
    olt::image_codec().decode(read_text(dir / "out/report" / file), cv::IMREAD_COLOR, picture, error);
    CHECK(error.empty());
    CHECK(picture.size() == cv::Size(2 * 300, 300));
    // Drawn over its picture by the page: itself thick, in its class's colour, titled with its id.
    const size_t at = html.find("<img src=\"" + file + "\""), end = html.find("</figure>", at);
    const std::string figure = html.substr(at, end - at);
    CHECK_THAT(figure, Catch::Contains("<svg viewBox=\"0 0 600 300\""));
    CHECK_THAT(figure, Catch::Contains("stroke-width=\"2\"><title>" + id + "</title></path>"));
    bool published = false;
    for (const auto& f : manifest["files"]) published |= f["path"] == "report/" + file;
    CHECK(published);
  }
}

// An annotator's edit: the pictures hold the scene only, so moving a box redraws its own picture (its
// crop moved) and no other, while its outline moves in every figure it shows in.
TEST_CASE("report: moving a box redraws its own picture only - its outline moves over the others") {
  TempDir dir;
  write_text(dir / "job.yaml", kJob);
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  auto boxes = nlohmann::json::parse(read_text(dir / "out/annotations/boxes.json"));
  REQUIRE(boxes["boxes"].size() >= 3);
  std::string job = kJob;
  const std::string from = "annotations: {kind: annotations, needs: [source]}";
  REQUIRE(job.find(from) != std::string::npos);
  job.replace(job.find(from), from.size(),
              "annotations: {kind: annotations, params: {file: boxes.json, frame: world}}");
  write_text(dir / "job.yaml", job);
  write_text(dir / "boxes.json", boxes.dump(1));
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);

  auto pictures = [&] {
    std::map<std::string, std::string> bytes;
    for (const auto& entry : fs::recursive_directory_iterator(dir / "out/report"))
      if (entry.path().extension() == ".png")
        bytes[entry.path().lexically_relative(dir / "out/report").string()] = read_text(entry.path());
    return bytes;
  };
  // The path a figure draws a box's edges with.
  auto edges = [](const std::string& html, const std::string& figure_file, const std::string& id) {
    const size_t figure = html.find("<img src=\"" + figure_file + "\""), end = html.find("</figure>", figure);
    const size_t title = html.find("><title>" + id + "</title>", figure);
    if (figure == std::string::npos || title == std::string::npos || title > end) return std::string();
    return html.substr(html.rfind("<path d=\"", title), title - html.rfind("<path d=\"", title));
  };
  const auto before = pictures();
  const std::string html_before = read_text(dir / "out/report/index.html");
  const std::string moved = boxes["boxes"][1]["id"], kept = boxes["boxes"][0]["id"];
  boxes["boxes"][1]["center"][0] = boxes["boxes"][1]["center"][0].get<double>() + 0.05;
  write_text(dir / "boxes.json", boxes.dump(1));
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  const auto after = pictures();
  const std::string html_after = read_text(dir / "out/report/index.html");

  // A picture per box and the scene's; the moved box stays inside the scene's region (5 cm within
  // the room), so the scene's picture is the same too.
  REQUIRE(before.size() == boxes["boxes"].size() + 1);
  REQUIRE(after.size() == before.size());
  for (const auto& [file, bytes] : before) {
    INFO(file);
    CHECK((after.at(file) == bytes) == (file != "boxes/" + moved + ".png"));
  }
  // In the scene's figure the moved box's edges moved, the kept box's did not.
  CHECK_FALSE(edges(html_before, "scene_boxes.png", moved).empty());
  CHECK(edges(html_before, "scene_boxes.png", moved) != edges(html_after, "scene_boxes.png", moved));
  CHECK_FALSE(edges(html_before, "scene_boxes.png", kept).empty());
  CHECK(edges(html_before, "scene_boxes.png", kept) == edges(html_after, "scene_boxes.png", kept));
}

// Headless Chromium (Debian's; docker/install-deps.sh installs it for the tests) opens a page that
// frames the report (file pages may read each other with --allow-file-access-from-files) and writes
// what it found into its DOM: the images, those that did not load, the links.
TEST_CASE("report: the page loads in headless Chromium with every image and no console message") {
  INFO("chromium not found: bash docker/install-deps.sh installs it (Debian package chromium)");
  REQUIRE(std::system("command -v chromium > /dev/null") == 0);
  TempDir dir;
  write_text(dir / "job.yaml", kJob);
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  write_text(dir / "frame.html", R"(<!doctype html><html><body>
<iframe id="report" src="out/report/index.html" width="1200" height="900"></iframe>
<script>
document.getElementById('report').onload = () => {
  const page = document.getElementById('report').contentDocument;
  const images = Array.from(page.images);
  const found = {
    images: images.map(i => i.getAttribute('src')),
    broken: images.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.getAttribute('src')),
    links: Array.from(page.querySelectorAll('a')).map(a => a.getAttribute('href')),
    svgs: page.querySelectorAll('svg').length,
    title: page.title
  };
  const out = document.createElement('pre');
  out.id = 'found';
  out.textContent = JSON.stringify(found);
  document.body.appendChild(out);
};
</script></body></html>
)");
  const std::string command =
      "chromium --headless --no-sandbox --disable-gpu --allow-file-access-from-files "
      "--enable-logging=stderr --v=0 --virtual-time-budget=10000 --dump-dom 'file://" +
      (dir / "frame.html").string() + "' > '" + (dir / "dom.html").string() + "' 2> '" +
      (dir / "browser.log").string() + "'";
  REQUIRE(std::system(command.c_str()) == 0);
  const std::string dom = read_text(dir / "dom.html"), log = read_text(dir / "browser.log");
  INFO(log);
  const auto begin = dom.find("<pre id=\"found\">"), end = dom.find("</pre>", begin);
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  std::string text = dom.substr(begin + 16, end - begin - 16);
  for (const auto& [from, to] : {std::pair{"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}})
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + 1))
      text.replace(at, std::strlen(from), to);
  const auto found = nlohmann::json::parse(text);
  INFO(found.dump(1));
  CHECK(found["title"] == "OLT report: job");
  CHECK(found["images"].size() >= 4 + 1 + 3);  // tiles, the scene, a picture per box
  CHECK(found["broken"].empty());
  CHECK(found["svgs"].get<int>() >= 2);  // the per-frame plot, the trajectory
  // Every link leads to a file of the output (the overlays beside the report).
  for (const auto& link : found["links"]) CHECK(fs::is_regular_file(dir / "out/report" / link.get<std::string>()));
  CHECK(found["links"].size() >= 8 + 4);             // every frame's point, every tile
  CHECK(log.find(":CONSOLE") == std::string::npos);  // no script error, no console message
}
