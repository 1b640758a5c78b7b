// Huge-page advice: the kernel is asked about the whole huge pages inside a buffer and about nothing
// around it. The advice marks those pages' mapping ("hg" among its VmFlags in /proc/self/smaps), so
// the test reads back what was advised.
#include "olt/core/huge_pages.h"

#include <sys/mman.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "olt/core/page_allocator.h"

namespace {

using Ranges = std::vector<std::pair<std::uintptr_t, std::uintptr_t>>;

// The parts of [lo, hi) that carry the huge-page advice, as ranges [start, end), those that touch
// joined: the kernel may merge an advised range with a neighbour advised as well, beyond [lo, hi).
Ranges advised_inside(std::uintptr_t lo, std::uintptr_t hi) {
  std::ifstream smaps("/proc/self/smaps");
  Ranges advised;
  std::uintptr_t start = 0, end = 0;
  for (std::string line; std::getline(smaps, line);) {
    if (line.find('-') != std::string::npos && line.find(' ') > line.find('-')) {
      std::istringstream range(line.substr(0, line.find(' ')));
      char dash = 0;
      range >> std::hex >> start >> dash >> end;
    } else if (line.rfind("VmFlags:", 0) == 0 && (line + " ").find(" hg ") != std::string::npos) {
      const std::uintptr_t from = std::max(start, lo), to = std::min(end, hi);
      if (from < to) advised.emplace_back(from, to);
    }
  }
  std::sort(advised.begin(), advised.end());
  Ranges joined;
  for (const auto& r : advised)
    if (!joined.empty() && joined.back().second == r.first)
      joined.back().second = r.second;
    else
      joined.push_back(r);
  return joined;
}

bool kernel_has_huge_pages() { return std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled").good(); }

}  // namespace

TEST_CASE("huge-page advice covers the whole huge pages inside a buffer and nothing outside it") {
  if (!kernel_has_huge_pages()) {
    WARN("skipped: this kernel has no transparent huge pages (/sys/kernel/mm/transparent_hugepage)");
    return;
  }
  const std::uintptr_t huge = olt::huge_page_bytes();
  const std::size_t mapped = 8 * huge;
  // Pages of the test's own, not advised (map_pages advises large ones).
  void* at = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(at != MAP_FAILED);
  const auto lo = reinterpret_cast<std::uintptr_t>(at), hi = lo + mapped;
  const std::uintptr_t first_huge = (lo + huge - 1) & ~(huge - 1);  // within the mapping's first huge page

  SECTION("a buffer of 4.5 huge pages that starts 12,345 bytes past a huge page's start") {
    olt::advise_huge_pages(reinterpret_cast<char*>(first_huge) + 12345, 4 * huge + huge / 2);
    // It ends 12,345 bytes past 4.5 pages: the pages from the next boundary on, three whole ones.
    CHECK(advised_inside(lo, hi) == Ranges{{first_huge + huge, first_huge + 4 * huge}});
  }
  SECTION("a buffer of one huge page's size that holds no whole huge page is left as it is") {
    olt::advise_huge_pages(reinterpret_cast<char*>(first_huge) + 1, huge);
    CHECK(advised_inside(lo, hi).empty());
  }
  SECTION("a buffer of exactly two huge pages") {
    olt::advise_huge_pages(reinterpret_cast<char*>(first_huge), 2 * huge);
    CHECK(advised_inside(lo, hi) == Ranges{{first_huge, first_huge + 2 * huge}});
  }
  munmap(at, mapped);
}

TEST_CASE("large blocks of the page allocator are advised, small ones not") {
  if (!kernel_has_huge_pages()) {
    WARN("skipped: this kernel has no transparent huge pages (/sys/kernel/mm/transparent_hugepage)");
    return;
  }
  const std::uintptr_t huge = olt::huge_page_bytes();
  void* large = olt::map_pages(4 * huge);
  const auto lo = reinterpret_cast<std::uintptr_t>(large);
  // Four huge pages' bytes hold four whole ones where the block starts on a boundary, else three.
  const Ranges advised = advised_inside(lo, lo + 4 * huge);
  REQUIRE(advised.size() == 1);
  CHECK(advised[0].second - advised[0].first == (lo % huge == 0 ? 4 : 3) * huge);
  CHECK(advised[0].first % huge == 0);
  olt::unmap_pages(large, 4 * huge);

  void* small = olt::map_pages(huge / 2);
  CHECK(advised_inside(reinterpret_cast<std::uintptr_t>(small), reinterpret_cast<std::uintptr_t>(small) + huge / 2)
            .empty());
  olt::unmap_pages(small, huge / 2);
}
