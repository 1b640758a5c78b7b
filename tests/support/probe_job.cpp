#include "support/probe_job.h"

#include <catch2/catch.hpp>

#include "support/temp_dir.h"

namespace olt::test {

namespace fs = std::filesystem;
using nlohmann::json;

json write_probe_job(const fs::path& dir, const std::string& labels_params) {
  const std::string head = R"(version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: 12, width: 160, height: 120}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  labels: {kind: propagate, needs: [poses, annotations], params: )" +
                           labels_params + "}\n";
  write_text(dir / "bootstrap.yaml", head + "  annotations: {kind: annotations, needs: [source]}\n");
  REQUIRE(run_olt("run " + (dir / "bootstrap.yaml").string()).exit_code == 0);
  json boxes = json::parse(read_text(dir / "out/annotations/boxes.json"));
  boxes["boxes"].push_back({{"id", "probe"},
                            {"label", "probe"},
                            {"center", {-1.2, -0.8, 0.1}},
                            {"size", {0.3, 0.3, 0.3}},
                            {"rotation", {0, 0, 0, 1}}});
  write_text(dir / "boxes.json", boxes.dump(1));
  write_text(dir / "job.yaml",
             head + "  annotations: {kind: annotations, needs: [source], params: {file: boxes.json}}\n");
  return boxes;
}

std::map<std::string, std::set<std::string>> boxes_seen(const fs::path& out) {
  std::map<std::string, std::set<std::string>> seen;
  for (const auto& entry : fs::directory_iterator(out / "labels/rgbd/frames")) {
    const json record = json::parse(read_text(entry.path()));
    for (const auto& b : record["boxes"]) seen[record["observation"]].insert(b["box"].get<std::string>());
  }
  return seen;
}

}  // namespace olt::test
