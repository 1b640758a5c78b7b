// Every shipped job publishes the bytes recorded in tests/golden/shipped_jobs.json: the net under any
// change meant to keep outputs as they are (a refactoring, a faster codec). An output that is meant
// to change is recorded again with tests/golden/record.sh, and the commit says why.
// Each job runs from a copy of jobs/ beside a link to ../shared (outputs land in a temporary folder,
// not in the repository) on a fresh cache; jobs whose data is absent are skipped, saying so.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "olt/core/hash.h"
#include "support/temp_dir.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

// path -> sha256 of every file the job published but the manifest.
std::map<std::string, std::string> published_digests(const fs::path& output) {
  std::map<std::string, std::string> digests;
  for (const auto& e : fs::recursive_directory_iterator(output)) {
    if (!e.is_regular_file()) continue;
    const std::string path = fs::relative(e.path(), output).string();
    if (path == "manifest.json") continue;
    digests[path] = olt::sha256_hex(read_text(e.path()));
  }
  return digests;
}

void check_shipped_job(const std::string& name) {
  const fs::path source = OLT_SOURCE_DIR;
  const auto golden = nlohmann::json::parse(read_text(source / "tests/golden/shipped_jobs.json"));
  REQUIRE(golden.contains(name));
  const std::string data = golden[name]["data"];
  if (!data.empty() && !fs::exists(fs::path(OLT_SHARED_DATA_DIR) / data)) {
    WARN("skipped: " << OLT_SHARED_DATA_DIR << "/" << data << " is absent");
    return;
  }
#ifndef OLT_TEST_WITH_MRPT
  if (name.find("rawlog") != std::string::npos) {
    WARN("skipped: built without libmrpt, which reads rawlogs");
    return;
  }
#endif
  TempDir dir;
  fs::create_directories(dir / "repo");
  fs::copy(source / "jobs", dir / "repo/jobs", fs::copy_options::recursive);
  fs::create_directory_symlink(fs::absolute(source / "../shared"), dir / "shared");
  ::setenv("OLT_CACHE_DIR", (dir / "cache").c_str(), 1);
  const auto run = run_olt("run " + (dir / "repo/jobs" / (name + ".yaml")).string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);

  std::map<std::string, std::string> expected;
  for (const auto& [path, digest] : golden[name]["files"].items()) expected[path] = digest;
  const auto published = published_digests(dir / "repo/out" / name);
  std::vector<std::string> differing;
  for (const auto& [path, digest] : expected) {
    auto it = published.find(path);
    if (it == published.end())
      differing.push_back(path + " (missing)");
    else if (it->second != digest)
      differing.push_back(path);
  }
  for (const auto& [path, digest] : published)
    if (!expected.count(path)) differing.push_back(path + " (new)");
  std::string list;
  for (size_t i = 0; i < differing.size() && i < 10; ++i) list += "\n  " + differing[i];
  INFO(differing.size() << " of " << expected.size() << " files differ from tests/golden/shipped_jobs.json" << list
                        << (differing.size() > 10 ? "\n  ..." : ""));
  CHECK(differing.empty());
}

}  // namespace

TEST_CASE("shipped job quickstart publishes its recorded bytes", "[heavy]") { check_shipped_job("quickstart"); }
TEST_CASE("shipped job tum_fr1_rpy publishes its recorded bytes", "[heavy]") { check_shipped_job("tum_fr1_rpy"); }
TEST_CASE("shipped job tum_fr1_rpy_registration publishes its recorded bytes", "[heavy]") {
  check_shipped_job("tum_fr1_rpy_registration");
}
TEST_CASE("shipped job sena_laser_map publishes its recorded bytes", "[heavy]") { check_shipped_job("sena_laser_map"); }
TEST_CASE("shipped job sena_laser_map_rawlog publishes its recorded bytes", "[heavy]") {
  check_shipped_job("sena_laser_map_rawlog");
}
TEST_CASE("shipped job synthetic_robot_laser publishes its recorded bytes", "[heavy]") {
  check_shipped_job("synthetic_robot_laser");
}

TEST_CASE("every shipped job has recorded bytes") {
  const fs::path source = OLT_SOURCE_DIR;
  const auto golden = nlohmann::json::parse(read_text(source / "tests/golden/shipped_jobs.json"));
  for (const auto& e : fs::directory_iterator(source / "jobs"))
    if (e.path().extension() == ".yaml") {
      INFO(e.path().filename().string() << ": record it with tests/golden/record.sh and add a test case");
      CHECK(golden.contains(e.path().stem().string()));
    }
}
