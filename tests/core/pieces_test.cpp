// Spooled text: what outgrows its memory waits in a temporary file and comes back in order, the
// same bytes; where no file can be made or written, the text is held whole, nothing lost.
#include "olt/core/pieces.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace olt;

namespace {

// 10,000 parts of varying length, as an export adds its frames' annotations.
std::string fill(SpooledText& spool) {
  std::string expected;
  for (int i = 0; i < 10000; ++i) {
    const std::string part = std::to_string(i) + std::string(static_cast<size_t>(i % 37), 'a' + i % 26) + ",";
    spool.append(part);
    expected += part;
  }
  return expected;
}

std::string read_back(const SpooledText& spool) {
  std::string text;
  spool.for_each_piece([&](std::string_view piece) { text += piece; });
  return text;
}

std::FILE* no_file() { return nullptr; }
std::FILE* read_only_file() { return std::fopen("/dev/null", "r"); }  // every write fails
std::FILE* memory_file() {  // a file without a descriptor, large enough for what the tests spill
  static char space[1 << 20];
  return fmemopen(space, sizeof(space), "w+");
}
std::FILE* small_disk() {  // 5,000 bytes, then full: the first spills fit, a later one fails
  static char space[5000];
  return fmemopen(space, sizeof(space), "w+");
}

}  // namespace

TEST_CASE("spooled text: beyond its memory it waits in a file, and comes back in order, read as often as asked") {
  SpooledText spool(1000);
  CHECK(spool.empty());
  const std::string expected = fill(spool);
  CHECK(spool.spilled());
  CHECK(spool.size() == expected.size());
  CHECK(read_back(spool) == expected);
  spool.append("tail");  // after a read, added at the end
  CHECK(read_back(spool) == expected + "tail");
  SpooledText moved = std::move(spool);
  CHECK(read_back(moved) == expected + "tail");
  CHECK(spool.empty());  // NOLINT(bugprone-use-after-move): moved from, empty by contract

  SpooledText small(1000);
  small.append("short");
  CHECK(small.held_bytes() < 1000);
  CHECK_FALSE(small.spilled());
  CHECK(read_back(small) == "short");
}

TEST_CASE("spooled text: what it holds in memory never grows past its memory bytes") {
  SpooledText spool(1000);
  std::string expected;
  size_t most = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::string part(static_cast<size_t>(1 + i % 97), static_cast<char>('a' + i % 26));
    spool.append(part);
    expected += part;
    most = std::max(most, spool.held_bytes());
  }
  CHECK(spool.spilled());
  CHECK(most <= 1000);                  // grown by doubling, it reached 1,920
  const std::string longer(5000, 'y');  // a part longer than its memory: written out, its buffer let go
  spool.append(longer);
  CHECK(spool.held_bytes() <= 1000);
  CHECK(read_back(spool) == expected + longer);
}

TEST_CASE("spooled text: with no file to spill to, or one that cannot be written, held whole - nothing lost") {
  SpooledText none(1000, no_file);
  const std::string expected = fill(none);
  CHECK_FALSE(none.spilled());
  CHECK(read_back(none) == expected);

  SpooledText failing(1000, read_only_file);
  const std::string again = fill(failing);
  CHECK_FALSE(failing.spilled());  // taken back into memory at the first failed write
  CHECK(read_back(failing) == again);

  SpooledText filling(1000, small_disk);
  const std::string third = fill(filling);
  CHECK_FALSE(filling.spilled());  // what was written is read back, the rest held
  CHECK(read_back(filling) == third);
}

TEST_CASE("spooled text: any part comes back by its offset, from the file or memory, on several threads at once") {
  SpooledText spool(1000);
  std::vector<std::pair<size_t, std::string>> parts;  // offset, text
  for (int i = 0; i < 3000; ++i) {
    std::string part = "{\"n\":" + std::to_string(i) + "," + std::string(static_cast<size_t>(i % 29), 'x') + "}";
    parts.emplace_back(spool.size(), part);
    spool.append(part);
  }
  REQUIRE(spool.spilled());
  std::vector<int> wrong(4, 0);
  std::vector<std::thread> readers;
  for (size_t t = 0; t < 4; ++t)
    readers.emplace_back([&, t] {
      for (size_t i = t; i < parts.size(); i += 4)
        wrong[t] += spool.read(parts[i].first, parts[i].second.size()) != parts[i].second;
    });
  for (auto& r : readers) r.join();
  CHECK(wrong == std::vector<int>(4, 0));
  const std::string whole = read_back(spool);
  CHECK(spool.read(10, 500) == whole.substr(10, 500));
  // The file's end and memory: at most 1,000 bytes are held after any append.
  CHECK(spool.read(whole.size() - 1500, 1500) == whole.substr(whole.size() - 1500));
  CHECK(spool.read(whole.size(), 0).empty());
  CHECK_THROWS_AS(spool.read(whole.size() - 1, 2), std::out_of_range);

  SpooledText none(1000, no_file);  // held whole
  const std::string expected = fill(none);
  CHECK(none.read(5, 40) == expected.substr(5, 40));

  SpooledText in_memory_file(1000, memory_file);  // spilled to a file without a descriptor
  const std::string again = fill(in_memory_file);
  REQUIRE(in_memory_file.spilled());
  CHECK(in_memory_file.read(100, 300) == again.substr(100, 300));
  CHECK(in_memory_file.read(again.size() - 1500, 1500) == again.substr(again.size() - 1500));
  CHECK(read_back(in_memory_file) == again);  // the stream still at its end for what follows
  in_memory_file.append("tail");
  CHECK(read_back(in_memory_file) == again + "tail");
}
