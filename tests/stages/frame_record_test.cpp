// A frame's record, made as text, is the compact JSON of the fields it names (keys sorted, as
// nlohmann writes them): the frames' cache keys are its hash, so a byte of difference would label
// every frame of every cache again.
#include <algorithm>
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

namespace {

// A frame's record (frame.json) as the document nlohmann dumps: what frame_record_text must write.
nlohmann::json expected_frame_json(const FrameInputs& f, const FrameLabels& labels, const FrameMasks& masks,
                                   const std::map<uint16_t, cv::Rect>& color_rects) {
  const auto rect = [](const cv::Rect& r) { return nlohmann::json{r.x, r.y, r.width, r.height}; };
  nlohmann::json boxes = nlohmann::json::array();
  for (size_t k = 0; k < f.boxes.size(); ++k) {
    const BoxInFrame& seen = labels.boxes[k];
    if (seen.covered_pixels == 0) continue;
    const LabeledBox& b = f.boxes[k];
    nlohmann::json j = {{"box", b.box.id},
                        {"label", b.box.label},
                        {"instance", b.box.instance},
                        {"class_id", b.class_id},
                        {"instance_id", b.instance_id},
                        {"labeled_pixels", seen.labeled_pixels},
                        {"covered_pixels", seen.covered_pixels},
                        {"bottom_pixels", seen.bottom_pixels},
                        {"visible_fraction", static_cast<double>(seen.labeled_pixels) / seen.covered_pixels}};
    if (const auto it = masks.masks.find(b.instance_id); it != masks.masks.end())
      j["bbox_depth"] = rect(it->second.bbox);
    if (const auto it = color_rects.find(b.instance_id); it != color_rects.end()) j["bbox_color"] = rect(it->second);
    if (!seen.bbox.empty()) j["box_bbox_depth"] = rect(seen.bbox);
    boxes.push_back(j);
  }
  return {{"observation", f.observation.id},
          {"sensor", f.observation.sensor},
          {"timestamp", f.observation.timestamp},
          {"pose", {{"valid", f.pose.valid}, {"flag", f.pose.flag}, {"quality", to_json(f.pose.quality)}}},
          {"valid_pixels", labels.valid_pixels},
          {"labeled_pixels", labels.labeled_pixels},
          {"ambiguous_pixels", labels.ambiguous_pixels},
          {"boxes", boxes}};
}

}  // namespace

TEST_CASE("frame record: frame.json's text is nlohmann's dump(1) of its document - any boxes, rectangles and quality") {
  const std::vector<Box> boxes = {box("chair \"1\"", "chair", 0.1),
                                  box("table",
                                      "t\xc3\xa4"
                                      "ble",
                                      0.2, 1),
                                  box("lamp", "lamp", 0.3)};
  const LabelMap map = make_label_map(boxes, {});
  const std::vector<LabeledBox> ordered = prioritized_boxes(boxes, map);
  Observation o;
  o.id = "1305031102.160407";
  o.sensor = "kinect\\2";
  o.timestamp = 1305031102.160407;
  ObservationPose pose;
  SensorCalibration cal;
  const DepthView view;
  // Instance ids 1..3 in a small image, so the colour rectangles (when the colour labels are their own
  // images) are those of their pixels.
  FrameLabels labels;
  labels.instance_ids = cv::Mat::zeros(6, 8, CV_16UC1);
  labels.instance_ids(cv::Rect(1, 1, 3, 2)).setTo(ordered[0].instance_id);
  labels.instance_ids(cv::Rect(5, 2, 2, 4)).setTo(ordered[1].instance_id);
  labels.valid_pixels = 40, labels.labeled_pixels = 14, labels.ambiguous_pixels = 1;
  // The third box covers pixels but labels none: no rectangle of its own, no mask; its instance has
  // pixels in the colour labels alone (a colour rectangle without a depth one).
  labels.boxes = {{6, 7, 2, cv::Rect(1, 1, 3, 2)}, {8, 9, 0, cv::Rect(5, 2, 2, 4)}, {0, 5, 0, cv::Rect()}};
  FrameMasks masks{labels.instance_ids.size(), {}};
  masks.masks[ordered[0].instance_id] = {"abc", 6, cv::Rect(1, 1, 3, 2)};
  masks.masks[ordered[1].instance_id] = {"de", 8, cv::Rect(5, 2, 2, 4)};
  ColorLabels own_color{cv::Mat(), labels.instance_ids.clone()};
  own_color.instance_ids(cv::Rect(0, 5, 2, 1)).setTo(ordered[2].instance_id);
  std::map<uint16_t, cv::Rect> own_color_rects = {{ordered[0].instance_id, cv::Rect(1, 1, 3, 2)},
                                                  {ordered[1].instance_id, cv::Rect(5, 2, 2, 4)},
                                                  {ordered[2].instance_id, cv::Rect(0, 5, 2, 1)}};
  const auto check = [&](const ColorLabels* color, const std::map<uint16_t, cv::Rect>& color_rects) {
    const FrameInputs f{o, pose, cal, view, ordered};
    CHECK(frame_record_text(f, labels, masks, color) == expected_frame_json(f, labels, masks, color_rects).dump(1));
  };
  SECTION("no quality, no colour labels") { check(nullptr, {}); }
  SECTION("colour labels of their own") { check(&own_color, own_color_rects); }
  SECTION("registered depth: the colour rectangles are the depth ones") {
    const ColorLabels registered{cv::Mat(), labels.instance_ids};
    std::map<uint16_t, cv::Rect> depth_rects;
    for (const auto& [id, mask] : masks.masks) depth_rects[id] = mask.bbox;
    check(&registered, depth_rects);
  }
  SECTION("a flagged pose with every part of its quality, nested") {
    pose.valid = false;
    pose.flag = "jump \"large\"";
    RegistrationQuality registration;
    registration.fit = RegistrationQuality::Fit{true, 12, 3400, 0.75, 0.0123, 5000, 4800, 2100, 0.031};
    registration.refined = true;
    pose.quality.registration = registration;
    pose.quality.laser = ScanQuality{41, 42, 0.033};
    pose.quality.consistency = ConsistencyQuality{0.9, 0.5, 0.02, 1200};
    check(&own_color, own_color_rects);
  }
  SECTION("no box covers a pixel") {
    for (auto& b : labels.boxes) b = BoxInFrame{};
    check(nullptr, {});
  }
  SECTION("a frame labeled in this run is counted as its record is read - boxes by place, unknown ones left out") {
    const FrameInputs f{o, pose, cal, view, ordered};
    const std::map<std::string, uint32_t> positions = {{"lamp", 0}, {"chair \"1\"", 2}, {"elsewhere", 1}};
    const auto check_counts = [&](const std::vector<std::string>& counted_ids) {
      std::vector<FrameCounts::Box> expected;  // in the frame's order
      for (size_t k = 0; k < ordered.size(); ++k)
        if (std::count(counted_ids.begin(), counted_ids.end(), ordered[k].box.id))
          expected.push_back(
              {positions.at(ordered[k].box.id), labels.boxes[k].labeled_pixels, labels.boxes[k].bottom_pixels});
      const FrameCounts counted = frame_counts_of(f, labels, positions);
      const FrameCounts read = frame_counts(frame_record_text(f, labels, masks, nullptr), positions);
      for (const FrameCounts& c : {counted, read}) {
        CHECK(c.labeled_pixels == 14);
        CHECK(c.depth_pixels == 40);
        CHECK(c.ambiguous_pixels == 1);
        REQUIRE(c.boxes.size() == expected.size());
        for (size_t k = 0; k < expected.size(); ++k) {
          CHECK(c.boxes[k].box == expected[k].box);
          CHECK(c.boxes[k].labeled_pixels == expected[k].labeled_pixels);
          CHECK(c.boxes[k].bottom_pixels == expected[k].bottom_pixels);
        }
      }
    };
    check_counts({"chair \"1\"", "lamp"});  // the table has no place; the lamp covers pixels, labels none
    for (size_t k = 0; k < ordered.size(); ++k)
      if (ordered[k].box.id == "lamp") labels.boxes[k] = BoxInFrame{};
    check_counts({"chair \"1\""});  // a box that covers no pixel is not in the record
  }
}
