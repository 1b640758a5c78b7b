// A frame's record, made as text, is the compact JSON of the fields it names (keys sorted, as
// nlohmann writes them): the frames' cache keys are its hash, so a byte of difference would label
// every frame of every cache again.
#include <catch2/catch.hpp>

#include "olt/core/hash.h"
#include "olt/model/recording.h"
#include "olt/propagate/label_map.h"
#include "stages/propagate_frame.h"

using namespace olt;

namespace {

Box box(const std::string& id, const std::string& label, double x, int priority = 0) {
  Box b;
  b.id = id;
  b.label = label;
  b.instance = id;
  b.T_world_box.translation() = Eigen::Vector3d(x, 0.5, 1);
  b.size = Eigen::Vector3d(0.3, 0.2, 0.1);
  b.priority = priority;
  return b;
}

// The record as a JSON document, field by field: what the text must be the compact dump of.
nlohmann::json expected_record(const Observation& o, const ObservationPose& pose, const std::vector<uint32_t>& in_view,
                               const std::vector<LabeledBox>& ordered, const LabelMap& map,
                               const SensorCalibration& cal, const PropagateConfig& c) {
  nlohmann::json boxes = nlohmann::json::object();
  for (uint32_t k : in_view) {
    const LabeledBox& b = ordered[k];
    const LabelClass* cls = map.find_class(b.class_id);
    const nlohmann::json j = {{"id", b.box.id},
                              {"label", b.box.label},
                              {"instance", b.box.instance},
                              {"class_id", b.class_id},
                              {"instance_id", b.instance_id},
                              {"color", cls ? nlohmann::json(cls->color) : nlohmann::json()},
                              {"pose", pose_to_json(b.box.T_world_box)},
                              {"size", {b.box.size.x(), b.box.size.y(), b.box.size.z()}},
                              {"priority", b.box.priority}};
    boxes[b.box.id] = sha256_hex(j.dump());
  }
  const bool color = (c.overlays || c.color_labels || c.point_clouds != CloudFiles::none) && o.color;
  return {{"frame_version", 6},
          {"overlays", c.overlays},
          {"color_labels", c.color_labels ? nlohmann::json{c.color_fill_px, c.color_fill_tolerance_m} : nullptr},
          {"point_clouds", name_of(c.point_clouds)},
          {"depth", o.depth.sha256.hex()},
          {"color", color ? o.color->sha256.hex() : ""},
          {"calibration", sha256_hex(to_json(cal).dump())},
          {"pose", sha256_hex(to_json(std::vector<ObservationPose>{pose}).dump())},
          {"boxes", boxes}};
}

}  // namespace

TEST_CASE(
    "frame record: its text is the compact JSON of its fields, keys sorted - boxes by id, whatever their priority") {
  // Ids whose order by priority is not their order by name, one needing escapes, one beginning with
  // a byte over 127 (after "zeta": names compare as unsigned bytes).
  const std::vector<Box> boxes = {box("zeta", "chair", 0.1, 2), box("alpha", "table", 0.2),
                                  box("m\"id\\\xc3\xbc", "chair", 0.3, 1), box("Beta", "cup", 0.4),
                                  box("\xc3\x84rger", "cup", 0.5, 3)};
  const LabelMap map = make_label_map(boxes, {});
  const std::vector<LabeledBox> ordered = prioritized_boxes(boxes, map);
  SensorCalibration cal;
  cal.depth.width = 64;
  cal.color.fx = 525.5;
  const Calibration calibration = {{"head", cal}, {"arm", SensorCalibration()}};
  Observation o;
  o.id = "0001";
  o.sensor = "head";
  o.depth.sha256 = Digest(sha256_hex("depth"));
  ObservationPose pose;
  pose.observation = "0001";
  pose.T_world_sensor.translation() = Eigen::Vector3d(1, 2, 3);

  PropagateConfig c;
  std::vector<uint32_t> in_view;
  SECTION("no box in view, no colour image") {}
  SECTION("every box, with a colour image and a point cloud") {
    in_view = {0, 1, 2, 3, 4};
    o.color = ImageFile{"c.png", Digest(sha256_hex("colour")), nullptr};
    c.point_clouds = CloudFiles::ply;
    c.color_fill_tolerance_m = 0.125;
  }
  SECTION("two boxes, colour unused: no overlays, no colour labels") {
    in_view = {3, 0};
    o.color = ImageFile{"c.png", Digest(sha256_hex("colour")), nullptr};
    c.overlays = false;
    c.color_labels = false;
  }
  const std::string text =
      frame_inputs_record(o, pose_digest(pose), in_view, record_parts(ordered, calibration, map, c));
  CHECK(text == expected_record(o, pose, in_view, ordered, map, cal, c).dump());
}

TEST_CASE("frame record: a fixed frame's key is the one recorded - a change to any frame's key is made on purpose") {
  // Every cache of every user holds frames under these keys: a change (a field, a box's or a
  // calibration's JSON, the frame version) labels every frame again. Record the new value only then.
  const std::vector<Box> boxes = {box("chair_1", "chair", 0.1), box("table", "table", 0.2, 1)};
  const LabelMap map = make_label_map(boxes, {});
  const std::vector<LabeledBox> ordered = prioritized_boxes(boxes, map);
  SensorCalibration cal;
  cal.depth.width = 640;
  cal.depth.height = 480;
  cal.depth.fx = cal.depth.fy = 525;
  Observation o;
  o.id = "1305031102.160407";
  o.sensor = "kinect";
  o.depth.sha256 = Digest(sha256_hex("depth"));
  o.color = ImageFile{"rgb.png", Digest(sha256_hex("colour")), nullptr};
  ObservationPose pose;
  pose.observation = o.id;
  pose.T_world_sensor.translation() = Eigen::Vector3d(1.25, -0.5, 1.5);
  const std::string text = frame_inputs_record(o, pose_digest(pose), {0, 1},
                                               record_parts(ordered, {{"kinect", cal}}, map, PropagateConfig()));
  CHECK(sha256_hex(text) == "2d7d9b92a296d5928a11810ca6abfc58c57625866f51ad95105162f5fd667f4d");
}
