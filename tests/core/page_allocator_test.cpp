// Huge-page advice: the kernel is asked about the whole 2 MB pages inside a buffer and about nothing
// around it (the advice splits the mapping, so /proc/self/smaps shows exactly what was advised).
#include "olt/core/page_allocator.h"

#include <sys/mman.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr std::uintptr_t kHuge = 2 << 20;

// The ranges [start, end) of this process's mappings inside [lo, hi) that carry the huge-page advice
// ("hg" among their VmFlags).
std::vector<std::pair<std::uintptr_t, std::uintptr_t>> advised_inside(std::uintptr_t lo, std::uintptr_t hi) {
  std::ifstream smaps("/proc/self/smaps");
  std::vector<std::pair<std::uintptr_t, std::uintptr_t>> advised;
  std::uintptr_t start = 0, end = 0;
  for (std::string line; std::getline(smaps, line);) {
    if (line.find('-') != std::string::npos && line.find(' ') > line.find('-')) {
      std::istringstream range(line.substr(0, line.find(' ')));
      char dash = 0;
      range >> std::hex >> start >> dash >> end;
    } else if (line.rfind("VmFlags:", 0) == 0 && (line + " ").find(" hg ") != std::string::npos && start >= lo &&
               end <= hi) {
      advised.emplace_back(start, end);
    }
  }
  return advised;
}

bool kernel_has_huge_pages() { return std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled").good(); }

}  // namespace

TEST_CASE("huge-page advice covers the whole 2 MB pages inside a buffer and nothing outside it") {
  if (!kernel_has_huge_pages()) {
    WARN("skipped: this kernel has no transparent huge pages (/sys/kernel/mm/transparent_hugepage)");
    return;
  }
  constexpr std::size_t kMapped = 16 << 20;
  // Pages of its own, not advised (map_pages advises large ones).
  void* mapped = mmap(nullptr, kMapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(mapped != MAP_FAILED);
  auto* base = static_cast<char*>(mapped);
  const auto lo = reinterpret_cast<std::uintptr_t>(base), hi = lo + kMapped;
  const std::uintptr_t first_huge = (lo + kHuge - 1) & ~(kHuge - 1);

  SECTION("a 9 MB buffer that starts 12,345 bytes past a huge page's start") {
    char* at = reinterpret_cast<char*>(first_huge) + 12345;
    olt::advise_huge_pages(at, 9 << 20);
    // From the next 2 MB boundary to the last one inside the buffer: three whole huge pages.
    const std::uintptr_t first = first_huge + kHuge,
                         last = (reinterpret_cast<std::uintptr_t>(at) + (9 << 20)) & ~(kHuge - 1);
    CHECK(last - first == 3 * kHuge);
    CHECK(advised_inside(lo, hi) == std::vector<std::pair<std::uintptr_t, std::uintptr_t>>{{first, last}});
  }
  SECTION("a buffer of 2 MB that holds no whole huge page is left as it is") {
    olt::advise_huge_pages(reinterpret_cast<char*>(first_huge) + 1, kHuge);
    CHECK(advised_inside(lo, hi).empty());
  }
  SECTION("a buffer of exactly the huge pages it spans") {
    olt::advise_huge_pages(reinterpret_cast<char*>(first_huge), 2 * kHuge);
    CHECK(advised_inside(lo, hi) ==
          std::vector<std::pair<std::uintptr_t, std::uintptr_t>>{{first_huge, first_huge + 2 * kHuge}});
  }
  munmap(base, kMapped);
}

TEST_CASE("large blocks of the page allocator are advised, small ones not") {
  if (!kernel_has_huge_pages()) {
    WARN("skipped: this kernel has no transparent huge pages (/sys/kernel/mm/transparent_hugepage)");
    return;
  }
  for (const std::size_t bytes : {std::size_t{8} << 20, std::size_t{1} << 20}) {
    INFO(bytes << " bytes");
    void* at = olt::map_pages(bytes);
    const auto lo = reinterpret_cast<std::uintptr_t>(at), hi = lo + bytes;
    const std::uintptr_t first = (lo + kHuge - 1) & ~(kHuge - 1), last = hi & ~(kHuge - 1);
    const auto advised = advised_inside(lo, hi);
    if (last > first)
      CHECK(advised == std::vector<std::pair<std::uintptr_t, std::uintptr_t>>{{first, last}});
    else
      CHECK(advised.empty());
    olt::unmap_pages(at, bytes);
  }
}
