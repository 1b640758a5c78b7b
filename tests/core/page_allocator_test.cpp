#include "olt/core/page_allocator.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

// Whether the byte at `at` is in one of this process's mappings (/proc/self/maps).
bool mapped(const void* at) {
  const auto address = reinterpret_cast<std::uintptr_t>(at);
  std::ifstream maps("/proc/self/maps");
  for (std::string line; std::getline(maps, line);) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream(line) >> std::hex >> lo >> dash >> hi;
    if (address >= lo && address < hi) return true;
  }
  return false;
}

// Blocks freed kept up to `bytes` while it lives; none kept after (what every test but this one
// expects: olt run keeps none).
struct FreedPagesKept {
  explicit FreedPagesKept(std::size_t bytes) { olt::keep_freed_pages(bytes); }
  ~FreedPagesKept() { olt::keep_freed_pages(0); }
  FreedPagesKept(const FreedPagesKept&) = delete;
  FreedPagesKept& operator=(const FreedPagesKept&) = delete;
};

}  // namespace

TEST_CASE("page blocks go back to the system at once unless freed ones are kept") {
  REQUIRE(olt::freed_pages_kept() == 0);
  void* block = olt::map_pages(256 << 10);
  std::memset(block, 7, 256 << 10);
  olt::unmap_pages(block, 256 << 10);
  CHECK_FALSE(mapped(block));
  CHECK(olt::freed_pages_kept() == 0);
}

TEST_CASE("a block freed is handed out again for a block of its size in pages, with its pages") {
  const FreedPagesKept kept(1 << 20);
  auto* block = static_cast<unsigned char*>(olt::map_pages(100'000));
  std::memset(block, 7, 100'000);
  olt::unmap_pages(block, 100'000);
  CHECK(mapped(block));
  CHECK(olt::freed_pages_kept() == 102'400);  // 25 pages of 4 KB
  // Another size is a block of its own; the same size in pages (not the same bytes) is the one kept.
  void* other = olt::map_pages(300'000);
  CHECK(other != block);
  CHECK(olt::map_pages(100'300) == block);
  CHECK(olt::freed_pages_kept() == 0);
  CHECK(block[99'999] == 7);  // the pages as they were: nothing mapped afresh
  olt::unmap_pages(block, 100'300);
  olt::unmap_pages(other, 300'000);
  CHECK(olt::freed_pages_kept() == 102'400 + 303'104);
}

TEST_CASE("blocks kept stay within their limit: the oldest go back first, and all when it is 0") {
  std::vector<void*> blocks;
  {
    const FreedPagesKept kept(3 * 65'536);
    for (int i = 0; i < 4; ++i) blocks.push_back(olt::map_pages(65'536));
    for (void* b : blocks) olt::unmap_pages(b, 65'536);
    CHECK(olt::freed_pages_kept() == 3 * 65'536);
    CHECK_FALSE(mapped(blocks[0]));  // the first freed made room for the last
    for (size_t i = 1; i < blocks.size(); ++i) CHECK(mapped(blocks[i]));
    // A block larger than the limit is never kept.
    void* large = olt::map_pages(4 * 65'536);
    olt::unmap_pages(large, 4 * 65'536);
    CHECK_FALSE(mapped(large));
    CHECK(olt::freed_pages_kept() == 3 * 65'536);
  }
  CHECK(olt::freed_pages_kept() == 0);
  for (void* b : blocks) CHECK_FALSE(mapped(b));
}
