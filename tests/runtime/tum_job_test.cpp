// The real TUM fr1_rpy recording end to end (skipped when ../shared/data is absent).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"

using namespace olt::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// The repository's TUM job, pointed at `data`, writing into out_dir with its cache in cache_dir,
// reading the boxes at `boxes` in `format`.
std::string tum_job(const fs::path& data, const std::string& out_dir, const std::string& cache_dir,
                    const std::string& boxes, const std::string& format) {
  std::string job = read_text(fs::path(OLT_SOURCE_DIR) / "jobs/tum_fr1_rpy.yaml");
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = job.find(from);
    REQUIRE(at != std::string::npos);
    job.replace(at, from.size(), to);
  };
  replace("output: ../out/tum_fr1_rpy", "output: " + out_dir + "\ncache: " + cache_dir);
  replace("path: ../../shared/data/tum_fr1_rpy", "path: " + data.string());
  replace("trajectory: ../../shared/data/tum_fr1_rpy/groundtruth.txt",
          "trajectory: " + (data / "groundtruth.txt").string());
  replace("file: tum_fr1_rpy.boxes.json", "file: " + boxes + "\n      format: " + format);
  return job;
}

}  // namespace

TEST_CASE("TUM fr1_rpy: second run all cached and byte-identical - a moved box re-runs annotations and labels only") {
  const fs::path data = shared_data("tum_fr1_rpy");
  if (data.empty()) {
    WARN("skipped: ../shared/data/tum_fr1_rpy is absent");
    return;
  }
  TempDir dir;
  fs::copy_file(fs::path(OLT_SOURCE_DIR) / "jobs/tum_fr1_rpy.boxes.json", dir / "boxes.json");
  write_text(dir / "job.yaml", tum_job(data, "out", "cache", "boxes.json", "native"));
  const std::string run = "run " + (dir / "job.yaml").string();

  REQUIRE(run_olt(run).exit_code == 0);
  const auto manifest = json::parse(read_text(dir / "out/manifest.json"));
  int class_images = 0;
  for (const auto& f : manifest["files"])
    if (f["kind"] == "class_label") {
      ++class_images;
      CHECK(f["sensor"] == "kinect");
      CHECK(f["observation"]["timestamp"].get<double>() > 1305031229.0);
    }
  CHECK(class_images == 100);
  const auto labels = json::parse(read_text(dir / "out/labels.json"));
  CHECK(labels["classes"].size() >= 5);
  const std::string before = snapshot(dir / "out");

  const auto second = run_olt(run);
  REQUIRE(second.exit_code == 0);
  CHECK_THAT(second.err, Catch::Contains("8 stages: 0 ran, 8 cached"));
  CHECK(snapshot(dir / "out") == before);

  auto boxes = json::parse(read_text(dir / "boxes.json"));
  REQUIRE(!boxes["boxes"].empty());
  boxes["boxes"][0]["center"][2] = boxes["boxes"][0]["center"][2].get<double>() + 0.05;
  write_text(dir / "boxes.json", boxes.dump(2));
  Plan plan = plan_of(dir / "job.yaml");
  CHECK(plan.status ==
        only_running({"source", "calibrate", "poses", "scene", "annotations", "labels", "dataset", "report"},
                     {"annotations", "labels", "dataset", "report"}));
  CHECK(plan.reason["annotations"] == "file " + (dir / "boxes.json").string() + " changed");
  CHECK(plan.reason["labels"] == "input annotations changed");
  CHECK(plan.reason["dataset"] == "input labels will be re-run");
}

TEST_CASE("TUM fr1_rpy: boxes converted to each tool's format and read back give byte-identical labels") {
  const fs::path data = shared_data("tum_fr1_rpy");
  if (data.empty()) {
    WARN("skipped: ../shared/data/tum_fr1_rpy is absent");
    return;
  }
  TempDir dir;
  const std::string native = (fs::path(OLT_SOURCE_DIR) / "jobs/tum_fr1_rpy.boxes.json").string();
  write_text(dir / "native.yaml", tum_job(data, "out_native", "cache", native, "native"));
  REQUIRE(run_olt("run " + (dir / "native.yaml").string()).exit_code == 0);
  for (const std::string format : {"labelcloud", "labelcloud_vertices", "sustechpoints", "supervisely"}) {
    INFO("format " << format);
    const fs::path converted = dir / (format + ".json");
    REQUIRE(run_olt("boxes convert --from=native --to=" + format + " " + native + " " + converted.string()).exit_code ==
            0);
    write_text(dir / (format + ".yaml"), tum_job(data, "out_" + format, "cache", converted.string(), format));
    REQUIRE(run_olt("run " + (dir / (format + ".yaml")).string()).exit_code == 0);
    CHECK(snapshot(dir / "out_native/labels/kinect/class") ==
          snapshot(dir / ("out_" + format + "/labels/kinect/class")));
    // labelCloud has no instances (each box becomes its own); the others keep them
    if (format.rfind("labelcloud", 0) != 0)
      CHECK(snapshot(dir / "out_native/labels/kinect/instance") ==
            snapshot(dir / ("out_" + format + "/labels/kinect/instance")));
  }
}
