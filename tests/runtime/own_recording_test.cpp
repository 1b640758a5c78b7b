// A user's own recording on the first try: JPEG colour labels end to end, a mistake repeated on
// every frame is said once with a count, and `format: tum` reads depth in TUM's units by default.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"
#include "support/tiny_recording.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

// path -> bytes of the class label images below `out`.
std::map<std::string, std::string> class_images(const fs::path& out) {
  std::map<std::string, std::string> images;
  for (const auto& e : fs::recursive_directory_iterator(out))
    if (e.is_regular_file() && e.path().parent_path().filename() == "class")
      images[fs::relative(e.path(), out).generic_string()] = read_text(e.path());
  return images;
}

fs::path labeled(const fs::path& root, const std::string& color_extension, const std::string& job) {
  run_tiny_tum_job(root, job, kTinyTumBoxes, color_extension);
  return root / "out";
}

}  // namespace

TEST_CASE("a TUM recording with JPEG colour is labeled end to end, as with PNG colour") {
  TempDir dir;
  const std::string job = std::string(kTinyTumJob) + "  dataset: {kind: export, needs: [labels]}\n";
  const auto png = class_images(labeled(dir / "png", ".png", job));
  const fs::path out = labeled(dir / "jpeg", ".jpg", job);
  const auto jpeg = class_images(out);
  REQUIRE(png.size() == 3);
  CHECK(jpeg == png);  // labels come from depth: the colour format changes none
  const auto coco = nlohmann::json::parse(read_text(out / "dataset/instances.json"));
  REQUIRE(coco["images"].size() == 3);
  for (const auto& image : coco["images"]) {
    const std::string file = image["file_name"];
    CHECK(file.substr(file.size() - 4) == ".jpg");
    CHECK(fs::is_regular_file(out / "dataset" / coco["info"]["olt_image_root"].get<std::string>() / file));
  }
}

TEST_CASE("one mistake on every frame is said three times, then once with a count and the lines") {
  TempDir dir;
  write_tiny_tum_recording(dir / "data");
  std::string rgb_list;
  for (int i = 0; i < 10; ++i) {
    write_text(dir / ("data/rgb/bad" + std::to_string(i) + ".jpg"), "not a picture\n");
    rgb_list += std::to_string(1.0 + 0.01 * i) + " rgb/bad" + std::to_string(i) + ".jpg\n";
  }
  write_text(dir / "data/rgb.txt", rgb_list);
  write_text(dir / "job.yaml", kTinyTumJob);
  write_text(dir / "boxes.json", kTinyTumBoxes);
  const auto run = run_olt("validate " + (dir / "job.yaml").string());
  INFO(run.err);
  CHECK(run.exit_code == 2);
  for (int line = 1; line <= 3; ++line)
    CHECK_THAT(run.err, Catch::Contains("rgb.txt:" + std::to_string(line) + ":1: colour image rgb/bad" +
                                        std::to_string(line - 1) + ".jpg: not an image OpenCV reads"));
  CHECK_THAT(run.err, Catch::Contains("rgb.txt:4:1: ... and 7 more colour images with this problem (lines 4 to "
                                      "10): not an image OpenCV reads"));
  CHECK(run.err.find("rgb/bad4.jpg") == std::string::npos);
  CHECK_THAT(run.err, Catch::Contains("invalid input (4 problems)"));
}

TEST_CASE("format: tum reads depth in TUM's 5000 units per metre unless the job says otherwise") {
  TempDir dir;
  std::string without_scale = kTinyTumJob;
  const std::string scale = ", depth_scale: 5000";
  const auto at = without_scale.find(scale);
  REQUIRE(at != std::string::npos);
  without_scale.erase(at, scale.size());
  // Depth 1.0-1.04 m: inside the box at 1 m in TUM's units; 5 m away, outside it, in millimetres.
  const auto given = class_images(labeled(dir / "given", ".png", kTinyTumJob));
  const auto by_default = class_images(labeled(dir / "default", ".png", without_scale));
  CHECK(by_default == given);
  std::string millimetres = without_scale;
  millimetres.replace(millimetres.find("depth_intrinsics"), 0, "depth_scale: 1000, ");
  CHECK(class_images(labeled(dir / "mm", ".png", millimetres)) != given);
}

// An instance drawn as two boxes (a desk and its return): the frame record's bbox_depth and
// bbox_color cover the whole instance in every box's entry; box_bbox_depth each box's own pixels.
TEST_CASE("frame records: bbox_depth and bbox_color cover the instance, box_bbox_depth the box") {
  TempDir dir;
  // Depth 1.0-1.04 m across the whole 64x48 view (fx 50: 0.64 m wide at 1 m): the left and right
  // thirds of the view, one instance.
  run_tiny_tum_job(dir.path(), kTinyTumJob, R"({"version": 1, "boxes": [
    {"id": "left", "label": "desk", "instance": "desk_1", "center": [-0.22, 0, 1], "size": [0.2, 0.6, 0.3], "rotation": [0, 0, 0, 1]},
    {"id": "right", "label": "desk", "instance": "desk_1", "center": [0.22, 0, 1], "size": [0.2, 0.6, 0.3], "rotation": [0, 0, 0, 1]}]})");
  const auto record = nlohmann::json::parse(read_text(dir / "out/labels/rgbd/frames/0.json"));
  REQUIRE(record["boxes"].size() == 2);
  const auto& left = record["boxes"][0]["box"] == "left" ? record["boxes"][0] : record["boxes"][1];
  const auto& right = record["boxes"][0]["box"] == "left" ? record["boxes"][1] : record["boxes"][0];
  CHECK(left["bbox_depth"] == right["bbox_depth"]);
  CHECK(left["bbox_color"] == left["bbox_depth"]);  // registered: the colour camera is the depth camera
  const auto own_left = left["box_bbox_depth"], own_right = right["box_bbox_depth"], all = left["bbox_depth"];
  CHECK(own_left != own_right);
  // The instance's rectangle is the union of its boxes' rectangles.
  CHECK(all[0] == own_left[0]);
  CHECK(all[0].get<int>() + all[2].get<int>() == own_right[0].get<int>() + own_right[2].get<int>());
  CHECK(own_left[0].get<int>() + own_left[2].get<int>() < own_right[0].get<int>());  // a gap between them
}
