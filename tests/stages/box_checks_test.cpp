// Wrong boxes are said, not passed silently: each case on the tiny TUM recording (a wall 1.0-1.04 m
// in front of a camera at the origin looking along +z) gives its warning in the log and in
// labels.json, and a good box gives none.
#include "stages/box_checks.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"
#include "support/tiny_recording.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

struct Outcome {
  std::string log;
  nlohmann::json labels;
};

Outcome labeled(const std::string& box) {
  TempDir dir;
  const std::string log = run_tiny_tum_job(dir.path(), kTinyTumJob, R"({"version": 1, "boxes": [)" + box + "]}");
  return {log, nlohmann::json::parse(read_text(dir / "out/labels.json"))};
}

}  // namespace

TEST_CASE("box checks: a good box labels pixels in every frame and gets no warning") {
  const auto good = labeled(
      R"({"id": "b1", "label": "wall", "center": [0, 0, 1], "size": [0.5, 0.5, 0.5], "rotation": [0, 0, 0, 1]})");
  CHECK(good.labels["warnings"].empty());
  CHECK(good.labels["boxes"]["b1"]["frames_labeled"] == 3);
  CHECK(good.labels["boxes"]["b1"]["pixels"].get<int>() > 100);
  CHECK(good.labels["instance_counts"]["b1"]["frames"] == 3);
  CHECK(good.log.find("warning") == std::string::npos);
}

TEST_CASE("box checks: each kind of wrong box is named with what to do") {
  struct Case {
    const char* name;
    const char* box;
    const char* said;
  };
  for (const Case& c : {
           Case{"behind the camera", R"("center": [0, 0, -2], "size": [0.5, 0.5, 0.5], "rotation": [0, 0, 0, 1])",
                "no frame sees it"},
           Case{"in front of the wall, holding nothing",
                R"("center": [0, 0, 0.5], "size": [0.2, 0.2, 0.2], "rotation": [0, 0, 0, 1])", "labels no pixel"},
           Case{"in millimetres", R"("center": [0, 0, 1000], "size": [500, 500, 500], "rotation": [0, 0, 0, 1])",
                "millimetres"},
           // Standing on the wall (its z axis towards the camera): its bottom face 1 cm behind the
           // wall's surface, so what it labels is the wall it stands on.
           Case{"swallowing its support",
                R"("center": [0, 0, 0.905], "size": [0.3, 0.3, 0.21], "rotation": [1, 0, 0, 0])",
                "within 2 cm of its bottom face"},
           Case{"yaw in radians",
                R"("center": [0, 0, 1], "size": [0.5, 0.5, 0.5], "yaw_pitch_roll_deg": [0.5236, 0, 0])",
                "are they radians?"},
       }) {
    INFO(c.name);
    const auto outcome = labeled(std::string(R"({"id": "b1", "label": "thing", )") + c.box + "}");
    CHECK_THAT(outcome.log, Catch::Contains("warning") && Catch::Contains(c.said));
    if (std::string(c.name) != "yaw in radians") {
      REQUIRE(outcome.labels["warnings"].size() == 1);
      CHECK_THAT(outcome.labels["warnings"][0].get<std::string>(),
                 Catch::Contains("box 'b1'") && Catch::Contains(c.said));
    }
  }
}

TEST_CASE("box checks: a frame record's counts, read keeping only the counted members, are its counts") {
  // The members a record holds besides the counted ones (rectangles, fractions, the pose) are
  // dropped while it is parsed; nested ones named like counted ones must not be taken for them.
  const std::string record = R"({
 "ambiguous_pixels": 4,
 "boxes": [
  {"bbox_depth": [1, 2, 3, 4], "bottom_pixels": 5, "box": "b1", "covered_pixels": 55, "instance": "i1",
   "label": "box", "labeled_pixels": 54, "visible_fraction": 0.98, "extra": {"labeled_pixels": 999}},
  {"box": "b2", "instance": "i2", "label": "book", "labeled_pixels": 0}
 ],
 "pose": {"labeled_pixels": 7, "boxes": [{"box": "no"}]},
 "labeled_pixels": 54,
 "valid_pixels": 3000
})";
  // Boxes by their position in the stage's list (b2 first there); one the list lacks is left out.
  const olt::FrameCounts counts = olt::frame_counts(record, {{"b2", 0}, {"b1", 1}});
  CHECK(counts.labeled_pixels == 54);
  CHECK(counts.depth_pixels == 3000);
  CHECK(counts.ambiguous_pixels == 4);
  REQUIRE(counts.boxes.size() == 2);
  CHECK(counts.boxes[0].box == 1);
  CHECK(counts.boxes[0].labeled_pixels == 54);
  CHECK(counts.boxes[0].bottom_pixels == 5);
  CHECK(counts.boxes[1].box == 0);
  CHECK(counts.boxes[1].bottom_pixels == 0);
  const olt::FrameCounts without_b1 = olt::frame_counts(record, {{"b2", 0}});
  REQUIRE(without_b1.boxes.size() == 1);
  CHECK(without_b1.boxes[0].box == 0);
}
