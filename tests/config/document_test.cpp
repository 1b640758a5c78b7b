// Documents read with positions: limits that keep a small file from standing for a huge one.
#include "olt/config/document.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"

using namespace olt;

TEST_CASE("a YAML file of aliases repeating each other is refused at its line, before it exhausts memory") {
  // 9 levels of 10 aliases each: 10^9 values from under 1 KB.
  std::string text = "l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level < 9; ++level) {
    const std::string previous = "*l" + std::to_string(level - 1);
    text += "l" + std::to_string(level) + ": &l" + std::to_string(level) + " [";
    for (int i = 0; i < 10; ++i) text += (i ? ", " : "") + previous;
    text += "]\n";
  }
  REQUIRE(text.size() < 1024);
  try {
    parse_yaml("bomb.yaml", text);
    FAIL("the aliases expand to 10^9 values");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("bomb.yaml:") && Catch::Contains("too many values"));
  }
  // The same shape, small, is fine.
  CHECK(parse_yaml("small.yaml", "a: &a [1, 2]\nb: [*a, *a]\n").value["b"][1][1] == 2);
}
