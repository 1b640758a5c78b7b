// The report's frame ranking, on hand-computed shares; the stages' sentences on known summaries.
#include "stages/report_frames.h"

#include <catch2/catch.hpp>

#include "olt/stages/sentences.h"

using namespace olt;

namespace {

ReportFrame frame(const std::string& sensor, int labeled, int depth = 100) {
  static const auto of_sensor = [](const char* id) {
    Observation o;
    o.id = "f";
    o.sensor = id;
    return o;
  };
  static const Observation a = of_sensor("a"), b = of_sensor("b");  // what the frames point to
  ReportFrame f;
  f.observation = sensor == "a" ? &a : &b;
  f.labeled = labeled >= 0;
  f.labeled_pixels = labeled < 0 ? 0 : labeled;
  f.depth_pixels = depth;
  return f;
}

}  // namespace

TEST_CASE("report: a frame's labeled share against its neighbours' median, its sensor's only") {
  // Shares 40 40 10 40 40 %, the camera "b" in the middle of them at 90 %.
  std::vector<ReportFrame> frames{frame("a", 40), frame("a", 40), frame("a", 10),
                                  frame("b", 90), frame("a", 40), frame("a", 40)};
  CHECK(share_against_neighbours(frames, 2, 2) == Approx(0.25));  // 10 / median(40, 40, 40)
  CHECK(share_against_neighbours(frames, 3, 2) == 1);             // no other frame of b
  // Frame 0's neighbours within 2: 40 and 10 -> the median of two is the larger (40).
  CHECK(share_against_neighbours(frames, 0, 2) == Approx(1.0));
  // Unlabeled (skipped) frames are not neighbours and not ranked.
  frames[1] = frame("a", -1);
  CHECK(share_against_neighbours(frames, 2, 2) == Approx(0.25));
  const auto worst = worst_frames(frames, 6);
  REQUIRE(worst.size() == 1);  // the others hold at least 0.9 of their neighbours' share
  CHECK(worst[0] == 2);
  CHECK(worst_frames(frames, 0).empty());
}

TEST_CASE("report: the worst frames come lowest share first, as many as asked") {
  std::vector<ReportFrame> frames;
  for (int share : {50, 50, 20, 50, 50, 5, 50, 50, 35, 50, 50}) frames.push_back(frame("a", share));
  CHECK(worst_frames(frames, 6) == std::vector<size_t>{5, 2, 8});
  CHECK(worst_frames(frames, 2) == std::vector<size_t>{5, 2});
}

TEST_CASE("stage sentences: counts with their nouns, shares as percentages, warnings counted") {
  CHECK(stage_sentence("source", {{"observations", 100}, {"without_color", 2}}) ==
        "read 100 RGB-D observations (2 without colour)");
  CHECK(stage_sentence("annotations", {{"boxes", 1}}) == "read 1 box");
  CHECK(stage_sentence("annotations", {{"boxes", 7}, {"warnings", {"w1", "w2"}}}) ==
        "read 7 boxes; 2 warnings (listed at the end)");
  CHECK(stage_sentence("propagate", {{"observations_labeled", 98},
                                     {"observations_skipped", 2},
                                     {"frames_labeled", 3},
                                     {"frames_reused", 95},
                                     {"labeled_pixels", 250},
                                     {"depth_pixels", 1000},
                                     {"ambiguous_pixels", 1},
                                     {"classes", {{"a", 1}, {"b", 2}}},
                                     {"instances", {{"a_1", 1}}}}) ==
        "labeled 98 observations (3 relabeled, 95 unchanged), skipped 2 (flagged poses); 25% of their depth pixels "
        "inside a box, 0.1% inside more than one; 2 classes, 1 instance seen");
  CHECK(stage_sentence("poses", {{"observations", 50}, {"flagged", {{{"observation", "1"}}}}}) ==
        "posed 49 observations; 1 of 50 observations (2%) flagged and left out");
  CHECK(stage_sentence("laser_map", {{"scans", 224},
                                     {"keyframes", 164},
                                     {"loop_closures", 44},
                                     {"map_points", 10436},
                                     {"path_length_m", 76.94},
                                     {"flagged", nlohmann::json::array()}}) ==
        "mapped 224 scans along a 76.9 m path: 164 keyframes, 44 loop closures, 10436 map points");
  CHECK(stage_sentence("propagate", {{"frames_labeled", 3}, {"frames_reused", 1}}) ==
        "3 frames labeled, 1 already in the cache");  // a shard's part
  CHECK(stage_sentence("no_such_kind", {{"a", 1}}) == R"({"a":1})");
  CHECK(percent(1, 3) == "33.3%");
  CHECK(percent(1, 2000) == "0.05%");
  CHECK(percent(0, 0) == "0%");
}

TEST_CASE(
    "report: the trajectory of a pose far off keeps about ten grid lines - flagged poses at their sensor's nearest") {
  auto pose = [](const std::string& sensor, double t, double x, bool valid) {
    ObservationPose p;
    p.sensor = sensor;
    p.timestamp = t;
    p.valid = valid;
    p.T_world_sensor = Pose::Identity();
    p.T_world_sensor.translation() = Eigen::Vector3d(x, 0, 0);
    return p;
  };
  const std::string far = trajectory_svg({pose("a", 0, 0, true), pose("a", 1, 1e6, true)});
  size_t lines = 0;
  for (size_t at = far.find("<line"); at != std::string::npos; at = far.find("<line", at + 1)) ++lines;
  CHECK(lines <= 25);
  // Flagged: at 1.2 s, nearest valid of its sensor at 1 s (x = 2 m); sensor b has no valid pose: not drawn.
  const std::string svg = trajectory_svg(
      {pose("a", 0, 0, true), pose("a", 1, 2, true), pose("a", 1.2, 0, false), pose("b", 1.1, 0, false)});
  size_t red = 0;
  for (size_t at = svg.find("fill=\"#e0301e\""); at != std::string::npos; at = svg.find("fill=\"#e0301e\"", at + 1))
    ++red;
  CHECK(red == 1);
  const std::string valid_end = svg.substr(svg.find("points=\"") + 8);
  const std::string last_x =
      valid_end.substr(valid_end.find(' ') + 1, valid_end.find(',', valid_end.find(' ')) - valid_end.find(' ') - 1);
  CHECK_THAT(svg, Catch::Contains("<circle cx=\"" + last_x + "\""));  // drawn where the 1 s pose is
}
