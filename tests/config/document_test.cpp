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

TEST_CASE("a JSON document's positions are where its keys and values stand, as the YAML parser finds them") {
  const std::string text =
      "{\n"
      "  \"boxes\": [\n"
      "    {\"label\": \"chair\", \"size\": [1, 2.5, 3]},\n"
      "    { \"label\" : \"caf\\u00e9 \\\"x\\\"\",\n"
      "      \"a/b~c\": {\"deep\": [true, null, {\"k\": \"}\"}]}, \"e\": 7 }\n"
      "  ],\n"
      "  \"n\": -1e3\n"
      "}\n";
  const Document json = parse_json_document("boxes.json", text);
  const Document yaml = parse_yaml("boxes.json", text);  // JSON is YAML: the reference positions
  REQUIRE(json.json_positions);
  const auto same = [&](const std::string& pointer) {
    INFO(pointer);
    CHECK(json.where(pointer).line == yaml.where(pointer).line);
    CHECK(json.where(pointer).column == yaml.where(pointer).column);
    CHECK(json.where_key(pointer).line == yaml.where_key(pointer).line);
    CHECK(json.where_key(pointer).column == yaml.where_key(pointer).column);
  };
  for (const auto& [pointer, position] : yaml.values) same(pointer);
  CHECK(yaml.values.size() == 18);
  // Values the text has, by hand: the escaped key, a key with '/' and '~', one escaped as a
  // surrogate pair (which yaml-cpp cannot read).
  CHECK(json.where("/boxes/1/label").line == 4);
  CHECK(json.where("/boxes/1/label").column == 17);
  CHECK(json.where_key("/boxes/1/a~1b~0c/deep/2/k").column == 39);
  const Document emoji = parse_json_document("e.json", "{\"x\": 1,\n \"\\ud83d\\ude00\": [0, 7]}");
  CHECK(emoji.where("/\xF0\x9F\x98\x80/1").line == 2);
  CHECK(emoji.where("/\xF0\x9F\x98\x80/1").column == 22);
  // A byte order mark is not a column.
  const Document marked = parse_json_document("m.json", "\xEF\xBB\xBF{\"a\": [1, 2]}");
  CHECK(marked.where("/a/1").line == 1);
  CHECK(marked.where("/a/1").column == 11);
  // What the text does not have: the nearest enclosing value.
  CHECK(json.where("/boxes/0/colour").line == 3);
  CHECK(json.where("/boxes/0/colour").column == 5);
  CHECK(json.where_key("/boxes/7/label").line == 2);
  CHECK(json.where("/n/x").line == 7);
  CHECK(json.where("/boxes/99999999999999999999999").line == 2);
  CHECK(json.where("/boxes/01").line == 2);  // not an index, as JSON pointers write them
  CHECK(json.where("/boxes/-1").line == 2);
}

TEST_CASE("a JSON document's duplicate key is refused at its line") {
  try {
    parse_json_document("dup.json", "{\"a\": 1,\n \"b\": {\"c\": 2,\n  \"c\": 3}}");
    FAIL("a duplicate key");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("dup.json:3:") && Catch::Contains("duplicate key 'c'"));
  }
}
