// Outputs do not depend on where a job is checked out: the same job in two folders at different
// depths (two CI runners) publishes the same file names with the same bytes, and the paths the
// outputs name (COCO's image root) are relative, so they resolve in either checkout.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"
#include "support/tiny_recording.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

const std::string kJob = std::string(kTinyTumJob) +
                         "  dataset: {kind: export, needs: [labels]}\n"
                         "  report: {kind: report, needs: [labels, scene]}\n";

// Relative path -> bytes of every file below `dir`.
std::map<std::string, std::string> files_below(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).generic_string()] = read_text(e.path());
  return files;
}

fs::path checkout(const fs::path& root) {
  run_tiny_tum_job(root, kJob);
  return root / "out";
}

}  // namespace

TEST_CASE("the same job checked out in two folders publishes byte-identical outputs") {
  TempDir dir;
  ::unsetenv("OLT_CACHE_DIR");  // each checkout's own cache (the job names one)
  const auto a = files_below(checkout(dir / "a"));
  const auto b = files_below(checkout(dir / "runner/two/b"));
  REQUIRE(a.size() > 5);
  std::vector<std::string> names_a, names_b;
  for (const auto& [name, bytes] : a) names_a.push_back(name);
  for (const auto& [name, bytes] : b) names_b.push_back(name);
  REQUIRE(names_a == names_b);
  for (const auto& [name, bytes] : a) {
    INFO(name);
    CHECK(bytes == b.at(name));
    CHECK(bytes.find(dir.path().string()) == std::string::npos);  // no absolute path of either checkout
  }

  // COCO's image root is relative to instances.json's folder and finds every image from there.
  const fs::path dataset = dir / "runner/two/b/out/dataset";
  const auto coco = nlohmann::json::parse(read_text(dataset / "instances.json"));
  const std::string root = coco["info"]["olt_image_root"];
  CHECK(fs::path(root).is_relative());
  REQUIRE(coco["images"].size() == 3);
  for (const auto& image : coco["images"]) {
    const std::string file = image["file_name"];
    INFO(file);
    CHECK(fs::is_regular_file(dataset / root / file));
  }
}

TEST_CASE("a generated recording's COCO images are published beside instances.json") {
  TempDir dir;
  write_text(dir / "job.yaml",
             "version: 1\noutput: out\ncache: cache\nstages:\n"
             "  source: {kind: source, params: {format: synthetic, frames: 4, width: 64, height: 48}}\n"
             "  calibrate: {kind: calibrate, needs: [source]}\n"
             "  poses: {kind: poses, needs: [calibrate]}\n"
             "  annotations: {kind: annotations, needs: [source]}\n"
             "  labels: {kind: propagate, needs: [poses, annotations]}\n"
             "  dataset: {kind: export, needs: [labels]}\n");
  const auto run = run_olt("run " + (dir / "job.yaml").string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const fs::path dataset = dir / "out/dataset";
  const auto coco = nlohmann::json::parse(read_text(dataset / "instances.json"));
  CHECK(coco["info"]["olt_image_root"] == "images");
  REQUIRE(!coco["images"].empty());
  for (const auto& image : coco["images"]) {
    const std::string file = image["file_name"];
    INFO(file);
    CHECK(fs::is_regular_file(dataset / "images" / file));
  }
}
