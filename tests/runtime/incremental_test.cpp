// Incremental relabelling: after one box moves, only the frames that see it (before or after) are
// labeled again, `olt plan` says how many and why, and the result equals a run from scratch.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <set>

#include "support/probe_job.h"
#include "support/temp_dir.h"

using namespace olt::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

json labels_detail(const fs::path& job) {
  const auto plan = run_olt("plan --json " + job.string());
  REQUIRE(plan.exit_code == 0);
  INFO(plan.out);
  const json parsed = json::parse(plan.out);
  for (const auto& s : parsed["stages"])
    if (s["id"] == "labels") {
      REQUIRE(s.contains("detail"));
      return s["detail"];
    }
  FAIL("no labels stage in the plan");
  return json();
}

}  // namespace

TEST_CASE("moving one box relabels only the frames that see it - plan says which - same bytes as from scratch") {
  TempDir dir;
  // The synthetic room's boxes are all in every frame's view; the probe box is seen from the end of
  // the camera's arc only.
  json boxes = write_probe_job(dir.path());
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  const auto seen_before = boxes_seen(dir / "out");
  REQUIRE(seen_before.size() == 12);

  // The box seen by the fewest frames (but some).
  std::map<std::string, int> frames_of;
  for (const auto& [frame, boxes] : seen_before)
    for (const auto& b : boxes) ++frames_of[b];
  std::string moved;
  for (const auto& [box, n] : frames_of)
    if (moved.empty() || n < frames_of[moved]) moved = box;
  INFO("moved box " << moved << ", seen in " << frames_of[moved] << " of 12 frames");
  REQUIRE(frames_of[moved] < 12);

  for (auto& b : boxes["boxes"])
    if (b["id"] == moved) b["center"][2] = b["center"][2].get<double>() + 0.01;
  write_text(dir / "boxes.json", boxes.dump(1));

  const json detail = labels_detail(dir / "job.yaml");
  const int to_label = detail["frames_to_label"];
  CHECK(to_label + detail["frames_reused"].get<int>() == 12);
  CHECK(to_label < 12);
  CHECK(detail["frames_seeing_changed_box"] == json{{moved, to_label}});
  CHECK(detail["causes"].empty());

  const auto run = run_olt("run " + (dir / "job.yaml").string());
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.err, Catch::Contains("(" + std::to_string(to_label) + " relabeled, " + std::to_string(12 - to_label) +
                                      " unchanged)"));
  // Every frame that lists the box, before or after the move, was among those relabeled.
  const auto seen_after = boxes_seen(dir / "out");
  int listing = 0;
  for (const auto& [frame, boxes_before] : seen_before)
    listing += boxes_before.count(moved) || seen_after.at(frame).count(moved);
  CHECK(listing <= to_label);
  CHECK(listing > 0);

  // The same job from scratch, in a fresh cache, gives the same bytes.
  const std::string incremental = snapshot(dir / "out");
  fs::remove_all(dir / "out");
  fs::remove_all(dir / "cache");
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  CHECK(snapshot(dir / "out") == incremental);
}
