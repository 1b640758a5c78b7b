#include "olt/core/page_allocator.h"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

// `bytes` in whole pages of this machine.
std::size_t in_pages(std::size_t bytes) {
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  return (bytes + page - 1) / page * page;
}

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
  CHECK(olt::freed_pages_kept() == in_pages(100'000));
  // Another size is a block of its own; the same size in pages (not the same bytes) is the one
  // kept.
  void* other = olt::map_pages(in_pages(100'000) + 1);
  CHECK(other != block);
  CHECK(olt::map_pages(in_pages(100'000) - 1) == block);
  CHECK(olt::freed_pages_kept() == 0);
  CHECK(block[99'999] == 7);  // the pages as they were: nothing mapped afresh
  olt::unmap_pages(block, in_pages(100'000) - 1);
  olt::unmap_pages(other, in_pages(100'000) + 1);
  CHECK(olt::freed_pages_kept() == in_pages(100'000) + in_pages(in_pages(100'000) + 1));
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

TEST_CASE("blocks out when the limit is lowered are kept within the new one when they come back") {
  const FreedPagesKept kept(1 << 20);
  void* a = olt::map_pages(65'536);
  void* b = olt::map_pages(65'536);
  olt::unmap_pages(a, 65'536);
  olt::keep_freed_pages(65'536);  // a fits; b, still out, will have to go back when freed
  CHECK(olt::freed_pages_kept() == 65'536);
  olt::unmap_pages(b, 65'536);
  CHECK(olt::freed_pages_kept() == 65'536);
  CHECK_FALSE(mapped(a));  // the older made room for the latest
  CHECK(mapped(b));
}

TEST_CASE("a list on the page allocator grows, shrinks and is made again in the blocks it freed") {
  const FreedPagesKept kept(8 << 20);
  std::vector<const void*> first_blocks;
  for (int cycle = 0; cycle < 3; ++cycle) {
    std::vector<std::uint64_t, olt::PageAllocator<std::uint64_t>> list;
    for (std::uint64_t i = 0; i < 40'000; ++i) list.push_back(i * 3);  // grown by doubling
    list.shrink_to_fit();
    CHECK(list.size() == 40'000);
    CHECK(list[39'999] == 119'997);
    if (cycle == 0) first_blocks.push_back(list.data());
    if (cycle > 0) CHECK(list.data() == first_blocks[0]);  // the same sizes, the same blocks
  }
}
