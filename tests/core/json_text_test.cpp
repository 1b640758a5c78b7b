// Documents written a member at a time are the bytes of nlohmann's dump(1) of the whole: arrays at
// the top and nested in an object, empty arrays, nested objects, strings that need escaping.
#include "olt/core/json_text.h"

#include <catch2/catch.hpp>

using nlohmann::json;

TEST_CASE("json text: arrays written an element at a time equal dump(1) of the whole document") {
  const std::vector<json> elements = {
      {{"path", "labels/cam \"1\"/a.png"}, {"observation", {{"id", "7"}, {"timestamp", 1305031102.175304}}}},
      json::array({1, 2, json::object()}),
      "plain",
      {{"nested", {{"deeper", json::array({json::object({{"x", 1}})})}}}}};
  const auto element = [&](size_t i) { return elements[i]; };

  std::string top;
  olt::append_array(top, elements.size(), element, 0);
  CHECK(top == json(elements).dump(1));

  std::string inside = "{\n \"files\": ";
  olt::append_array(inside, elements.size(), element, 1);
  inside += "\n}";
  CHECK(inside == json({{"files", elements}}).dump(1));

  std::string empty = "{\n \"files\": ";
  olt::append_array(empty, 0, element, 1);
  empty += "\n}";
  CHECK(empty == json({{"files", json::array()}}).dump(1));

  std::string nested;
  olt::append_nested(nested, elements[3], 0);
  CHECK(nested == elements[3].dump(1));
}
