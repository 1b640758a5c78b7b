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

  // Drained to a "file" after each element: the pieces make the same text.
  std::string drained, pieces = "{\n \"files\": ";
  int drains = 0;
  olt::append_array(pieces, elements.size(), element, 1, [&](std::string& so_far) {
    drained += so_far;
    so_far.clear();
    ++drains;
  });
  drained += pieces + "\n}";
  CHECK(drains == 4);
  CHECK(drained == json({{"files", elements}}).dump(1));
}

TEST_CASE("json text: elements read one at a time at a depth - the manifest's entries, a list's objects") {
  const json manifest = {{"files", {{{"path", "a"}, {"observation", {{"id", "7"}}}}, {{"path", "b"}}}}};
  std::vector<json> seen;
  olt::for_each_at(manifest.dump(1), 2, [&](const json& j) { seen.push_back(j); });
  REQUIRE(seen.size() == 2);
  CHECK(seen[0] == manifest["files"][0]);  // nested objects come whole, not one by one
  CHECK(seen[1] == manifest["files"][1]);

  seen.clear();
  olt::for_each_at("[{\"x\": 1}, 2, \"three\"]", 1, [&](const json& j) { seen.push_back(j); });
  CHECK(seen == std::vector<json>{{{"x", 1}}, 2, "three"});
  CHECK_THROWS_AS(olt::for_each_at("[{\"x\": 1},", 1, [](const json&) {}), json::parse_error);
}

TEST_CASE("json text: a string quoted as nlohmann quotes it - its own way for plain ASCII, nlohmann's for the rest") {
  std::vector<std::string> strings = {"",
                                      "rgbd/class/1305031102.175304.png",
                                      "a\"b",
                                      "back\\slash",
                                      "tab\there",
                                      "line\nbreak",
                                      "\x7f",
                                      "caf\xc3\xa9",
                                      "\xe2\x82\xac 5",
                                      std::string("nul\0inside", 10)};
  for (int c = 1; c < 0x80; ++c) strings.push_back("x" + std::string(1, static_cast<char>(c)) + "y");
  for (const std::string& s : strings) {
    CAPTURE(s);
    CHECK(olt::json_string(s) == nlohmann::json(s).dump());
  }
  CHECK_THROWS_AS(olt::json_string("bad \xff utf-8"), nlohmann::json::type_error);  // as nlohmann refuses it
}
