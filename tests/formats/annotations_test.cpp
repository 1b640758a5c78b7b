#include "olt/formats/annotations.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"

using namespace olt;

namespace {

std::string errors_of(const std::string& text) {
  try {
    parse_native_annotations("boxes.json", text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("native annotations: quaternion and yaw-pitch-roll boxes") {
  const auto boxes = parse_native_annotations("boxes.json", R"({"version": 1, "boxes": [
    {"id": "b1", "label": "monitor", "instance": "monitor_1", "center": [1, 2, 3], "size": [0.5, 0.1, 0.4],
     "rotation": [0, 0, 0.7071068, 0.7071068]},
    {"id": "b2", "label": "book", "center": [0, 0, 0], "size": [1, 1, 1], "yaw_pitch_roll_deg": [90, 0, 0]}]})");
  REQUIRE(boxes.size() == 2);
  CHECK(boxes[0].instance == "monitor_1");
  CHECK(boxes[1].instance == "b2");  // defaults to the id
  CHECK(boxes[0].T_world_box.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  CHECK(boxes[0].T_world_box.linear().isApprox(boxes[1].T_world_box.linear(), 1e-6));
  // round trip through the writer
  const auto again = parse_native_annotations("x", format_native_annotations(boxes));
  CHECK(again[1].T_world_box.isApprox(boxes[1].T_world_box, 1e-12));
  CHECK(again[0].size.isApprox(boxes[0].size));
}

TEST_CASE("invalid boxes get errors naming the box - the field and the line") {
  const std::string text = R"({"version": 1, "boxes": [
  {"id": "a", "label": "x", "center": [0, 0, 0], "size": [1, -0.1, 1], "rotation": [0, 0, 0, 1]},
  {"id": "a", "label": "x", "center": [0, 0, 0], "size": [1, 1, 1], "rotation": [0, 0, 0, 2]}
]})";
  const std::string e = errors_of(text);
  CHECK_THAT(e,
             Catch::Contains("boxes.json:2:") && Catch::Contains("box 'a' (boxes[0]): size[1] must be > 0, got -0.1"));
  CHECK_THAT(e, Catch::Contains("boxes.json:3:") && Catch::Contains("box 'a' (boxes[1]): duplicate id 'a'"));
  CHECK_THAT(e, Catch::Contains("box 'a' (boxes[1]): rotation must be a unit quaternion"));
  CHECK_THAT(errors_of(R"({"version": 1, "boxes": [{"id": "a", "label": "x", "center": [0, 0, 0], "size": [1, 1, 1],
    "rotation": [0, 0, 0, 1], "yaw_pitch_roll_deg": [0, 0, 0]}]})"),
             Catch::Contains("boxes.json:1:") && Catch::Contains("/boxes/0"));
  CHECK_THAT(
      errors_of(R"({"version": 1, "boxes": [{"id": "a", "label": "x", "center": [0, 0, 0], "size": [1, 1, 1]}]})"),
      Catch::Contains("/boxes/0"));
  CHECK_THAT(errors_of("{\"version\": 1,\n \"boxes\": [,]}"),
             Catch::Contains("boxes.json:2:") && Catch::Contains("syntax error"));
}

TEST_CASE(
    "native annotations: priority and margin are read, written back, and a margin as high as the box is refused") {
  const auto boxes = parse_native_annotations("boxes.json", R"({"version": 1, "boxes": [
    {"id": "rug", "label": "rug", "center": [0, 0, 0], "size": [1, 1, 0.1], "rotation": [0, 0, 0, 1],
     "priority": 2, "margin": 0.02}]})");
  CHECK(boxes[0].priority == 2);
  CHECK(boxes[0].margin_m == 0.02);
  const auto again = parse_native_annotations("x", format_native_annotations(boxes));
  CHECK(again[0].priority == 2);
  CHECK(again[0].margin_m == 0.02);
  CHECK_THAT(
      errors_of(R"({"version": 1, "boxes": [{"id": "a", "label": "x", "center": [0, 0, 0], "size": [1, 1, 0.1],
    "rotation": [0, 0, 0, 1], "margin": 0.1}]})"),
      Catch::Contains("boxes.json:2:") &&
          Catch::Contains("box 'a' (boxes[0]): margin must be >= 0 and below the box's height (0.1 m), got 0.1"));
  // A box of no height and no margin: the size's error alone (a fuzzer found this one crashing).
  const std::string flat = errors_of(R"({"version": 1, "boxes": [{"id": "a", "label": "x", "center": [0, 0, 0],
    "size": [1, 1, 0.00], "yaw_pitch_roll_deg": [30, 0, 0]}]})");
  CHECK_THAT(flat, Catch::Contains("box 'a' (boxes[0]): size[2] must be > 0, got 0.0"));
  CHECK_THAT(flat, !Catch::Contains("margin"));
  // labeling_box: the bottom face raised by the margin along the box's own z axis
  Box tilted = boxes[0];
  tilted.T_world_box.linear() = rotation_from_ypr_deg(0, 0, 90);  // roll 90: the box's z is world -y
  const Box part = labeling_box(tilted);
  CHECK(part.size.z() == Approx(0.08));
  CHECK(part.T_world_box.translation().isApprox(tilted.T_world_box.linear().col(2) * 0.01));
}

TEST_CASE("native annotations written by OLT read back, trusted, to exactly the validated boxes") {
  const std::string written = format_native_annotations(parse_native_annotations("boxes.json", R"({"version": 1,
    "boxes": [{"id": "b1", "label": "monitor", "instance": "monitor_1", "center": [1.25, -2, 0.3],
               "size": [0.5, 0.1, 0.4], "rotation": [0.1, -0.2, 0.7, 0.6782]},
              {"id": "rug", "label": "rug", "center": [0, 0, 0], "size": [1, 1, 0.1], "yaw_pitch_roll_deg": [33, 2, -1],
               "priority": 2, "margin": 0.02}]})"));
  const auto validated = parse_native_annotations("boxes.json", written);
  const auto trusted = read_native_annotations(written);
  REQUIRE(trusted.size() == validated.size());
  for (size_t i = 0; i < trusted.size(); ++i) {
    CHECK(trusted[i].id == validated[i].id);
    CHECK(trusted[i].label == validated[i].label);
    CHECK(trusted[i].instance == validated[i].instance);
    CHECK(trusted[i].priority == validated[i].priority);
    CHECK(trusted[i].margin_m == validated[i].margin_m);
    CHECK(trusted[i].size == validated[i].size);
    CHECK(trusted[i].T_world_box.matrix() == validated[i].T_world_box.matrix());  // bit for bit
  }
  CHECK(format_native_annotations(trusted) == format_native_annotations(validated));
}

TEST_CASE("a key given twice in annotation JSON is an error at its second line, not the last one winning") {
  // A second "boxes" would silently replace the first: every pixel unlabeled.
  const std::string text = R"({"version": 1, "boxes": [
  {"id": "a", "label": "x", "center": [0, 0, 0], "size": [1, 1, 1], "rotation": [0, 0, 0, 1]}],
  "boxes": []})";
  CHECK_THAT(errors_of(text), Catch::Contains("boxes.json:3:") && Catch::Contains("duplicate key 'boxes'"));
  // Inside a box too.
  CHECK_THAT(errors_of(R"({"version": 1, "boxes": [{"id": "a", "label": "x", "label": "y", "center": [0, 0, 0],
    "size": [1, 1, 1], "rotation": [0, 0, 0, 1]}]})"),
             Catch::Contains("duplicate key 'label'"));
}
