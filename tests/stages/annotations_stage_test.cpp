// The annotations stage passes a format reader's warnings on (its summary shows them).
#include <catch2/catch.hpp>

#include "olt/stages/annotations.h"
#include "support/temp_dir.h"

using namespace olt;

TEST_CASE("annotations stage: radians read as degrees come with the warning naming labelcloud_rel") {
  test::TempDir dir;
  test::write_text(dir / "lc.json", R"({"objects": [{"name": "cup", "centroid": {"x": 0, "y": 0, "z": 0},
    "dimensions": {"length": 1, "width": 1, "height": 1}, "rotations": {"x": 0, "y": 0, "z": 0.5235987756}}]})");
  AnnotationsConfig config;
  config.format = "labelcloud";
  config.file = (dir / "lc.json").string();
  config.label_map = {{"cup", "mug"}};
  const BoxFile read = run_annotations({"annotations", ""}, config);
  REQUIRE(read.boxes.size() == 1);
  CHECK(read.boxes[0].label == "mug");
  REQUIRE(read.warnings.size() == 1);
  CHECK_THAT(read.warnings[0].str(), Catch::Contains("lc.json:") && Catch::Contains("format: labelcloud_rel"));
  config.format = "labelcloud_rel";
  CHECK(run_annotations({"annotations", ""}, config).warnings.empty());
}
