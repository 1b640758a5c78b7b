#include "support/temp_dir.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <vector>

namespace olt::test {

namespace fs = std::filesystem;

TempDir::TempDir() {
  std::random_device random;
  path_ = fs::temp_directory_path() / ("olt-test-" + std::to_string(::getpid()) + "-" + std::to_string(random()));
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void write_text(const fs::path& file, const std::string& text) {
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Completed run_olt(const std::string& args) {
  TempDir capture;
  const std::string command =
      std::string(OLT_BINARY) + " " + args + " >" + (capture / "out").string() + " 2>" + (capture / "err").string();
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(capture / "out"), read_text(capture / "err")};
}

std::string snapshot(const fs::path& dir) {
  std::vector<std::string> entries;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return "";
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) entries.push_back(fs::relative(e.path(), dir).string() + "\n" + read_text(e.path()));
  std::sort(entries.begin(), entries.end());
  std::string all;
  for (const auto& e : entries) all += e + "\n--\n";
  return all;
}

Plan plan_of(const fs::path& job) {
  const auto result = run_olt("plan --json " + job.string());
  INFO(result.err);
  REQUIRE(result.exit_code == 0);
  const nlohmann::json parsed = nlohmann::json::parse(result.out);
  Plan plan;
  for (const auto& s : parsed["stages"]) {
    plan.status[s["id"]] = s["status"];
    plan.reason[s["id"]] = s["reason"];
  }
  return plan;
}

std::map<std::string, std::string> only_running(const std::vector<std::string>& stages,
                                                const std::vector<std::string>& running) {
  std::map<std::string, std::string> status;
  for (const auto& id : stages) status[id] = std::count(running.begin(), running.end(), id) ? "run" : "cached";
  return status;
}

std::vector<uint32_t> decode_coco_rle(const std::string& s) {
  std::vector<int64_t> counts;
  size_t p = 0;
  while (p < s.size()) {
    int64_t x = 0;
    int k = 0;
    bool more = true;
    while (more) {
      const int64_t c = s[p] - 48;
      x |= (c & 0x1f) << (5 * k);
      more = c & 0x20;
      ++p;
      ++k;
      if (!more && (c & 0x10)) x |= static_cast<int64_t>(~uint64_t{0} << (5 * k));  // sign-extend
    }
    if (counts.size() > 2) x += counts[counts.size() - 2];
    counts.push_back(x);
  }
  return std::vector<uint32_t>(counts.begin(), counts.end());
}

fs::path shared_data(const std::string& name) {
  const fs::path dir = fs::path(OLT_SHARED_DATA_DIR) / name;
  std::error_code ec;
  return fs::exists(dir, ec) ? fs::canonical(dir) : fs::path();
}

}  // namespace olt::test
