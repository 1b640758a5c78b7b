// labelCloud files read with the wrong format: the other layout (centroid vs vertices) is named in
// one error; angles in the other unit give an error where they cannot be in the format's unit and a
// warning where they only look like the other; vertices that are not a box are refused.
#include <catch2/catch.hpp>

#include "olt/core/error.h"
#include "olt/formats/box_formats.h"

using namespace olt;

namespace {

// A centroid file of one box per rotation triple (x, y, z), as text.
std::string centroid_file(const std::vector<std::array<double, 3>>& rotations) {
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& r : rotations)
    objects.push_back({{"name", "cup"},
                       {"centroid", {{"x", 0}, {"y", 0}, {"z", 0}}},
                       {"dimensions", {{"length", 1}, {"width", 1}, {"height", 1}}},
                       {"rotations", {{"x", r[0]}, {"y", r[1]}, {"z", r[2]}}}});
  return nlohmann::json{{"objects", objects}}.dump(1);
}

std::vector<Diagnostic> errors_of(const std::string& format, const std::string& text) {
  try {
    read_boxes(format, "lc.json", text);
  } catch (const InputError& e) {
    return e.diagnostics();
  }
  return {};
}

std::vector<Diagnostic> warnings_of(const std::string& format, const std::string& text) {
  return read_box_file(format, "lc.json", text).warnings;
}

Box test_box() {
  Box b;
  b.id = b.label = b.instance = "cup";
  b.size = Eigen::Vector3d(0.4, 0.3, 0.2);
  b.T_world_box = pose_from_xyz_ypr_deg({1, 2, 3, 40, -15, 25});
  return b;
}

}  // namespace

TEST_CASE("labelCloud: a vertices file read as centroid (and back) is one error naming the format to use") {
  const std::string vertices = write_boxes("labelcloud_vertices", {test_box(), test_box()});
  for (const std::string format : {"labelcloud", "labelcloud_rel"}) {
    const auto errors = errors_of(format, vertices);
    REQUIRE(errors.size() == 1);
    CHECK_THAT(errors[0].message, Catch::Contains("format: labelcloud_vertices"));
    CHECK(errors[0].line > 0);
  }
  const auto errors = errors_of("labelcloud_vertices", write_boxes("labelcloud", {test_box(), test_box()}));
  REQUIRE(errors.size() == 1);
  CHECK_THAT(errors[0].message, Catch::Contains("format: labelcloud for degrees"));
}

TEST_CASE("labelCloud degrees that look like radians: a warning naming labelcloud_rel - boxes still read") {
  // 30 degrees written as radians, read as degrees, would silently become 0.52 degrees
  const std::string text = centroid_file({{0, 0, 0.5235987756}, {0, 0.1, 0}});
  const BoxFile read = read_box_file("labelcloud", "lc.json", text);
  CHECK(read.boxes.size() == 2);
  REQUIRE(read.warnings.size() == 1);
  CHECK_THAT(read.warnings[0].str(), Catch::StartsWith("lc.json:") && Catch::Contains("format: labelcloud_rel") &&
                                         Catch::Contains("objects[0].rotations.z = 0.5235987756"));
  // Real degree files: small round tilts, or any angle beyond 2 pi, or all zero
  CHECK(warnings_of("labelcloud", centroid_file({{2, 0, 5}, {0, 0.5, 0}})).empty());
  CHECK(warnings_of("labelcloud", centroid_file({{0.5235987756, 0, 123.4567}})).empty());
  CHECK(warnings_of("labelcloud", centroid_file({{0, 0, 0}})).empty());
}

TEST_CASE("labelCloud radians beyond 2 pi are an error naming labelcloud - beyond pi or whole numbers a warning") {
  const auto errors = errors_of("labelcloud_rel", centroid_file({{0, 0, 1.2}, {0, 0, 30}, {0, 350, 0}}));
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].str().rfind("lc.json:", 0) == 0);
  CHECK(errors[0].line > 0);
  CHECK_THAT(errors[0].message, Catch::Contains("objects[1].rotations.z = 30.0 (and 1 more)") &&
                                    Catch::Contains("beyond 2 pi") && Catch::Contains("format: labelcloud"));
  const auto outside = warnings_of("labelcloud_rel", centroid_file({{0, 0, 4.2}}));
  REQUIRE(outside.size() == 1);
  CHECK_THAT(outside[0].message, Catch::Contains("outside (-pi, pi]") && Catch::Contains("format: labelcloud"));
  const auto whole = warnings_of("labelcloud_rel", centroid_file({{0, 0, 3}, {1, 0, 0}}));
  REQUIRE(whole.size() == 1);
  CHECK_THAT(whole[0].message, Catch::Contains("whole number"));
  CHECK(warnings_of("labelcloud_rel", centroid_file({{0, 0, 3.14159265}, {-0.5, 0, 1.2}})).empty());
}

TEST_CASE("labelCloud vertices: rounded corners are a box - moved or mirrored corners are an error naming the object") {
  nlohmann::json file = nlohmann::json::parse(write_boxes("labelcloud_vertices", {test_box(), test_box()}));
  for (auto& v : file["objects"][1]["vertices"])
    for (auto& x : v) x = std::round(x.get<double>() * 1000) / 1000;  // export_precision 3
  const auto boxes = read_boxes("labelcloud_vertices", "v.json", file.dump(1));
  REQUIRE(boxes.size() == 2);
  CHECK((boxes[1].size - test_box().size).norm() < 2e-3);
  CHECK(boxes[1].T_world_box.linear().isApprox(test_box().T_world_box.linear(), 1e-2));

  nlohmann::json moved = file;
  moved["objects"][1]["vertices"][6][2] = moved["objects"][1]["vertices"][6][2].get<double>() + 0.05;
  auto errors = errors_of("labelcloud_vertices", moved.dump(1));
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].line > 1);
  CHECK_THAT(errors[0].message, Catch::Contains("objects[1] ('cup')") && Catch::Contains("do not form a box") &&
                                    Catch::Contains("vertex 6"));

  nlohmann::json mirrored = file;
  std::swap(mirrored["objects"][0]["vertices"][1], mirrored["objects"][0]["vertices"][3]);
  std::swap(mirrored["objects"][0]["vertices"][5], mirrored["objects"][0]["vertices"][7]);
  errors = errors_of("labelcloud_vertices", mirrored.dump(1));
  REQUIRE(errors.size() == 1);
  CHECK_THAT(errors[0].message, Catch::Contains("objects[0] ('cup')") && Catch::Contains("mirrored"));

  nlohmann::json short_list = file;
  short_list["objects"][0]["vertices"].erase(7);
  CHECK_THAT(errors_of("labelcloud_vertices", short_list.dump(1))[0].message, Catch::Contains("expected 8 corners"));
}
