// Typed pose quality: every shape a pose source writes reads back to the same JSON, text for text.
#include "olt/model/pose_quality.h"

#include <catch2/catch.hpp>

using namespace olt;

TEST_CASE("pose quality: each shape reads back and writes the same JSON") {
  const char* shapes[] = {
      "null",
      R"({"key":false})",
      R"({"first":true,"keyframe":0,"key":true,"new_keyframe":true})",
      R"({"converged":true,"inlier_ratio":0.875,"inliers":5210,"iterations":12,"key":true,"keyframe":3,)"
      R"("photometric_points":27001,"photometric_rmse":0.0412,"rmse_m":0.0123,"source_points":5954,)"
      R"("target_points":6020,"consistency":{"coverage":0.98,"fraction":0.91,"points":6000,"rmse_m":0.011}})",
      R"({"converged":false,"inlier_ratio":0.2,"inliers":10,"iterations":30,"key":true,"not_refined":"too far",)"
      R"("refined":false,"rmse_m":0.06,"source_points":50,"target_points":60})",
      R"({"scan_after":8,"scan_before":7,"scan_gap_s":0.1})",
      R"({"laser":{"scan_after":8,"scan_before":7,"scan_gap_s":0.1},"registration":{"converged":true,)"
      R"("inlier_ratio":0.9,"inliers":900,"iterations":5,"key":true,"refined":true,"rmse_m":0.01,)"
      R"("source_points":1000,"target_points":1100}})",
  };
  for (const char* text : shapes) {
    INFO(text);
    const nlohmann::json j = nlohmann::json::parse(text);
    CHECK(to_json(pose_quality_from_json(j)).dump() == j.dump());
  }
}

TEST_CASE("pose quality: the typed fields are what the JSON says") {
  const PoseQuality q = pose_quality_from_json(nlohmann::json::parse(
      R"({"laser":{"scan_after":8,"scan_before":7,"scan_gap_s":0.1},"registration":{"key":true,"refined":false,)"
      R"("not_refined":"correction too large"}})"));
  REQUIRE(q.laser);
  CHECK(q.laser->scan_before == 7);
  CHECK(q.laser->scan_after == 8);
  REQUIRE(q.registration);
  CHECK(q.registration->refined == false);
  CHECK(q.registration->not_refined == "correction too large");
  CHECK_FALSE(q.registration->fit);
  CHECK_FALSE(q.consistency);
  CHECK(pose_quality_from_json(nullptr).empty());
  CHECK(to_json(PoseQuality{}).is_null());
}
