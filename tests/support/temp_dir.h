#pragma once
// Test helpers: a temporary folder removed at the end of the test, and running the olt binary.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace olt::test {

class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

struct Completed {
  int exit_code = 0;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// Runs the built `olt` with `args` (shell words, already quoted as needed).
Completed run_olt(const std::string& args);

void write_text(const std::filesystem::path& file, const std::string& text);
std::string read_text(const std::filesystem::path& file);
/// Every regular file below `dir` with its content, for "nothing changed" checks.
std::string snapshot(const std::filesystem::path& dir);

/// `olt plan --json JOB` as stage id -> status and stage id -> reason (REQUIREs exit code 0).
struct Plan {
  std::map<std::string, std::string> status, reason;
};
Plan plan_of(const std::filesystem::path& job);

/// The plan statuses of a job of `stages` when exactly `running` would run.
std::map<std::string, std::string> only_running(const std::vector<std::string>& stages,
                                                const std::vector<std::string>& running);

/// Run lengths of a COCO compressed RLE string: the COCO API's rleFrString, written independently
/// of olt's encoder (pycocotools itself is not packaged for Debian 12).
std::vector<uint32_t> decode_coco_rle(const std::string& counts);

/// ../shared/data/<name>, or "" when absent (tests then skip with a message).
std::filesystem::path shared_data(const std::string& name);

}  // namespace olt::test
