// The report's scene: its points are decoded only for a picture the cache does not hold, and a
// report made from the cache alone is the same page and pictures as one drawn from the points.
#include <atomic>
#include <catch2/catch.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "olt/core/made_once.h"
#include "olt/stages/report.h"

using namespace olt;

namespace {

// 2,000 points spread over a 2 m x 2 m x 1 m room, coloured by height.
std::shared_ptr<const ScenePoints> room() {
  auto points = std::make_shared<ScenePoints>();
  points->voxel_size_m = 0.02f;
  for (int i = 0; i < 2000; ++i) {
    const float x = static_cast<float>(i % 40) * 0.05f, y = static_cast<float>((i / 40) % 40) * 0.05f;
    const float z = static_cast<float>(i % 7) * 0.15f;
    points->cloud.push_back({x, y, z, static_cast<uint8_t>(i % 256), 100, static_cast<uint8_t>(z * 200)});
  }
  return points;
}

ReportInputs inputs_with(const std::function<std::shared_ptr<const ScenePoints>()>& points) {
  ReportInputs in;
  in.recording = std::make_shared<const Recording>();
  in.poses = std::make_shared<const std::vector<ObservationPose>>();
  in.labels_summary = nlohmann::json::object();
  Box chair;
  chair.id = "chair_1", chair.label = "chair", chair.instance = "chair_1";
  chair.T_world_box.translation() = Eigen::Vector3d(1.0, 0.8, 0.4);
  chair.size = Eigen::Vector3d(0.5, 0.5, 0.8);
  in.boxes = {chair};
  in.scene = ReportScene{points, 0.02f, "a digest of the points", Pose::Identity(), {}};
  return in;
}

}  // namespace

TEST_CASE("report: a second report whose pictures are in the cache decodes no point, and is the same") {
  std::map<std::string, std::string> cache;
  std::mutex cache_mutex;  // pictures are drawn in parallel
  const Memo memo = [&](const nlohmann::json& record, const std::function<std::string()>& make) {
    const std::lock_guard<std::mutex> lock(cache_mutex);
    const auto [at, added] = cache.emplace(record.dump(), std::string());
    if (added) at->second = make();
    return at->second;
  };
  std::atomic<int> decoded{0};
  const auto decode = [&] {
    ++decoded;
    return room();
  };

  ReportInputs first = inputs_with(made_once<ScenePoints>(decode));
  first.memo = memo;
  const ReportResult drawn = run_report(first, ReportConfig{});
  CHECK(decoded == 1);                  // once, for the box's picture, the scene's and the region, on two threads
  REQUIRE(drawn.pictures.size() == 2);  // the scene's and the chair's

  // A fresh run (a new process, as `olt run` after an edit elsewhere): everything from the cache.
  ReportInputs again = inputs_with(made_once<ScenePoints>(decode));
  again.memo = memo;
  const ReportResult found = run_report(again, ReportConfig{});
  CHECK(decoded == 1);
  CHECK(found.html == drawn.html);
  CHECK(found.pictures == drawn.pictures);

  // Without the cache each report decodes them, and draws the same.
  ReportInputs uncached = inputs_with(made_once<ScenePoints>(decode));
  const ReportResult redrawn = run_report(uncached, ReportConfig{});
  CHECK(decoded == 2);
  CHECK(redrawn.pictures == drawn.pictures);
}
