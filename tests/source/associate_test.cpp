#include "olt/source/associate.h"

#include <catch2/catch.hpp>

using namespace olt;

TEST_CASE("depth images pair with the nearest colour image within the limit") {
  const auto pairs = associate_nearest({1.00, 2.00, 3.00, 4.00}, {0.99, 1.02, 2.05, 3.015, 3.99}, 0.02);
  REQUIRE(pairs.size() == 4);
  CHECK(pairs[0] == std::optional<size_t>(0));  // 0.99 is nearer than 1.02
  CHECK_FALSE(pairs[1]);                        // 2.05 is 50 ms away
  CHECK(pairs[2] == std::optional<size_t>(3));
  CHECK(pairs[3] == std::optional<size_t>(4));
}
