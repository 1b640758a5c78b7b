// The report stage: one page with the pictures it names (the scene with its boxes, one picture per
// box), the class counts of the labels, the flagged observations.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>  // flags only

#include "olt/core/image_codec.h"
#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

TEST_CASE(
    "report: index.html with trajectory, scene with boxes, box pictures, contact sheet, class counts and flagged "
    "observations") {
  TempDir dir;
  write_text(dir / "job.yaml", R"(version: 1
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
)");
  const auto run = run_olt("run " + (dir / "job.yaml").string());
  REQUIRE(run.exit_code == 0);
  const std::string html = read_text(dir / "out/report/index.html");
  for (const char* picture : {"trajectory.png", "scene_boxes.png", "contact_sheet.jpg"}) {
    CHECK_THAT(html, Catch::Contains(std::string("src=\"") + picture + "\""));
    CHECK(fs::exists(dir / "out/report" / picture));
  }
  // 4 tiles of 80 px in one row, each 60 px high plus its caption.
  cv::Mat sheet;
  std::string error;
  olt::image_codec().decode(read_text(dir / "out/report/contact_sheet.jpg"), cv::IMREAD_COLOR, sheet, error);
  REQUIRE(error.empty());
  CHECK(sheet.cols == 4 * 80);
  CHECK(sheet.rows == 60 + 18);
  CHECK_THAT(html, Catch::Contains("8 observations labeled, 0 skipped"));
  CHECK_THAT(html, Catch::Contains("<h2>Flagged observations</h2>\n<ul>\n<li>none</li>"));
  // Every class of the run's summary, with its pixel and frame counts.
  const auto manifest = nlohmann::json::parse(read_text(dir / "out/manifest.json"));
  const auto labels = nlohmann::json::parse(read_text(dir / "out/labels.json"));
  REQUIRE(labels["classes"].size() >= 3);
  for (const auto& c : labels["classes"])
    CHECK_THAT(html, Catch::Contains("<tr><td>" + c["name"].get<std::string>() + "</td><td>"));
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
    bool published = false;
    for (const auto& f : manifest["files"]) published |= f["path"] == "report/" + file;
    CHECK(published);
  }
}
