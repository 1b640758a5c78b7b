// What `olt watch` keeps between cycles unless told: an eighth of the memory it may use
// (olt/core/usable_memory.h), from 512 MB (never more than a quarter of it) to 4 GB.
#include <catch2/catch.hpp>

#include "olt/watch/watch.h"

using namespace olt;

TEST_CASE("olt watch keeps an eighth of the memory it may use unless told, from 512 MB - at most a quarter - to 4 GB") {
  constexpr uint64_t kGiB = uint64_t{1} << 30;
  CHECK(default_image_memory_mb(0) == 512);  // unknown
  CHECK(default_image_memory_mb(2 * kGiB) == 512);
  CHECK(default_image_memory_mb(kGiB) == 256);  // a small pod: a quarter, not half
  CHECK(default_image_memory_mb(kGiB / 2) == 128);
  CHECK(default_image_memory_mb(8 * kGiB) == 1024);
  CHECK(default_image_memory_mb(24 * kGiB) == 3072);
  CHECK(default_image_memory_mb(256 * kGiB) == 4096);
}
