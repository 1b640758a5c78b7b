// A recording and its poses read from their text as they are parsed: the same values the whole
// document gives, and the same errors for text that is not one.
#include <catch2/catch.hpp>
#include <sstream>

#include "olt/model/recording.h"

using namespace olt;

namespace {

Recording sample_recording() {
  Recording r;
  SensorInfo s;
  s.id = "cam \"0\"";
  s.depth_width = 64, s.depth_height = 48, s.color_width = 128, s.color_height = 96;
  s.calibration = SensorCalibration{};
  s.calibration->depth_scale = 5000;
  r.sensors.push_back(s);
  r.sensors.push_back(SensorInfo{"cam1", 32, 24, 32, 24, std::nullopt});
  for (int i = 0; i < 300; ++i) {
    Observation o;
    o.id = std::to_string(1000 + i);
    o.sensor = i % 2 ? "cam1" : "cam \"0\"";
    o.timestamp = 1305031102.175304 + i * 0.033;
    o.depth = {"depth/" + o.id + ".png", Digest(std::string(64, "0123456789abcdef"[i % 16]))};
    if (i % 3) o.color = ImageFile{"rgb/" + o.id + ".jpg", Digest(std::string(64, 'e'))};
    o.color_dt_s = i % 5 ? 0.0 : 0.001 * i;
    r.observations.push_back(o);
  }
  r.groundtruth = "groundtruth.txt";
  r.root = "/data/rec";
  r.groundtruth_frame = "world";
  return r;
}

}  // namespace

TEST_CASE("a recording read from its text as it is parsed equals the one read from its whole document") {
  const Recording r = sample_recording();
  const std::string text = to_json(r).dump(1);
  std::istringstream in(text);
  const Recording streamed = recording_from_text(in);
  const Recording whole = recording_from_json(nlohmann::json::parse(text));
  CHECK(to_json(streamed).dump(1) == text);
  CHECK(to_json(whole).dump(1) == text);
  REQUIRE(streamed.observations.size() == 300);
  CHECK(streamed.observations[299].id == "1299");
  CHECK(streamed.observations[299].depth.sha256 == r.observations[299].depth.sha256);
  CHECK(streamed.sensors.size() == 2);
  CHECK(streamed.sensors[0].calibration->depth_scale == 5000);
  CHECK(streamed.observations.capacity() == 300);

  // Text that is not a recording: the same kinds of error as the whole document gives.
  for (const std::string& bad : {std::string("{"), text.substr(0, text.size() / 2), std::string("[]"),
                                 std::string(R"({"sensors": []})"),  // no observations: an error, not none
                                 std::string(R"({"sensors": [], "observations": [{"id": "1"}]})")}) {
    CAPTURE(bad);
    std::istringstream bad_in(bad);
    CHECK_THROWS_AS(recording_from_text(bad_in), nlohmann::json::exception);
  }
}

TEST_CASE("poses read from their text as they are parsed equal those read from the whole document") {
  std::vector<ObservationPose> poses;
  for (int i = 0; i < 200; ++i) {
    ObservationPose p;
    p.observation = std::to_string(i);
    p.sensor = "cam";
    p.timestamp = i * 0.1;
    p.T_world_sensor =
        Pose(Eigen::Translation3d(i * 0.01, -0.5, 1.25) * Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitZ()));
    p.valid = i % 7 != 0;
    p.flag = p.valid ? "" : "no scan within max_gap_s";
    if (i % 3 == 0) p.quality.laser = ScanQuality{7, 8, 0.1};
    poses.push_back(p);
  }
  const std::string text = to_json(poses).dump(1);
  std::istringstream in(text);
  const std::vector<ObservationPose> streamed = poses_from_text(in);
  // (A pose read back may differ from the one written in its last bits: the rotation is renormalised.)
  CHECK(to_json(streamed).dump(1) == to_json(poses_from_json(nlohmann::json::parse(text))).dump(1));
  REQUIRE(streamed.size() == 200);
  CHECK(streamed[199].timestamp == poses[199].timestamp);
  CHECK(streamed[7].flag == "no scan within max_gap_s");
  CHECK(streamed[198].T_world_sensor.translation().isApprox(poses[198].T_world_sensor.translation()));
  std::string made;  // made a pose at a time: dump(1)'s bytes
  poses_text(poses, [&](std::string_view piece) { made += piece; });
  CHECK(made == text);
  made.clear();
  poses_text({}, [&](std::string_view piece) { made += piece; });
  CHECK(made == "[]");
  std::istringstream empty("[]");
  CHECK(poses_from_text(empty).empty());
  for (const std::string& bad : {std::string("{}"), std::string("[{\"observation\": \"1\"}]"), text.substr(0, 100)}) {
    CAPTURE(bad);
    std::istringstream bad_in(bad);
    CHECK_THROWS_AS(poses_from_text(bad_in), nlohmann::json::exception);
  }
}

TEST_CASE("a recording's text made an observation at a time is dump(1)'s, byte for byte") {
  Recording r = sample_recording();
  r.groundtruth = "groundtruth.txt";
  r.root = "/data/with \"quotes\"\n and a line break";
  const std::vector<Observation> some = r.observations;
  for (int k = 0; k < 20; ++k) r.observations.insert(r.observations.end(), some.begin(), some.end());
  std::string text;
  size_t pieces = 0;
  recording_text(r, [&](std::string_view piece) { text += piece, ++pieces; });
  CHECK(text == to_json(r).dump(1));
  CHECK(pieces >= 2);  // 6,300 observations: more than a megabyte
  r.observations.clear();
  text.clear();
  recording_text(r, [&](std::string_view piece) { text += piece; });
  CHECK(text == to_json(r).dump(1));
  CHECK(text.find("\"observations\": []") != std::string::npos);
}
