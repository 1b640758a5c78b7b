// The TUM source's check of its images: every header read, each problem said with its list's line;
// in a process that keeps memory (`olt watch` checks them every cycle), a file that is the same to a
// stat (inode, size, time) is not read again, unless its time was within 2 s of the read.
#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>

#include "stages/source_formats.h"
#include "support/keeping_memory.h"
#include "support/temp_dir.h"
#include "support/tiny_recording.h"

using namespace olt;
using namespace olt::test;

namespace {

std::vector<Diagnostic> checked(const fs::path& dir) {
  std::vector<Diagnostic> errors;
  source::check_tum_images(dir, errors);
  return errors;
}

}  // namespace

TEST_CASE("TUM images checked again by olt watch: a file the same to a stat is not read again, one changed is") {
  TempDir dir;
  write_tiny_tum_recording(dir / "data");
  const fs::path depth = dir / "data/depth/0.png";
  const auto spoil = [&](size_t size) {  // garbage of `size` bytes in the same file (inode)
    std::fstream file(depth, std::ios::binary | std::ios::in | std::ios::out);
    file << std::string(size, 'x');
  };
  const uintmax_t size = fs::file_size(depth);
  const auto hour_ago = fs::last_write_time(depth) - std::chrono::hours(1);
  fs::last_write_time(depth, hour_ago);

  SECTION("kept") {
    KeepingMemory keeping;
    REQUIRE(checked(dir / "data").empty());
    spoil(size);
    fs::last_write_time(depth, hour_ago);
    CHECK(checked(dir / "data").empty());  // the header read before: the file was not opened
    spoil(size + 1);                       // another size (and time): read again
    const auto errors = checked(dir / "data");
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].file == (dir / "data/depth.txt").string());
    CHECK_THAT(errors[0].message, Catch::Contains("depth/0.png"));
  }
  SECTION("a process that keeps nothing reads every header every time") {
    REQUIRE(checked(dir / "data").empty());
    spoil(size);
    fs::last_write_time(depth, hour_ago);
    CHECK(checked(dir / "data").size() == 1);
  }
  SECTION("a file whose time is within 2 s of the read, or after it (a clock ahead), is read again") {
    KeepingMemory keeping;
    const auto just_now = fs::file_time_type::clock::now() + std::chrono::hours(1);
    fs::last_write_time(depth, just_now);
    REQUIRE(checked(dir / "data").empty());
    spoil(size);
    fs::last_write_time(depth, just_now);
    CHECK(checked(dir / "data").size() == 1);
  }
}
