#include "runtime/publish_list.h"

#include <catch2/catch.hpp>
#include <deque>
#include <nlohmann/json.hpp>
#include <sstream>

using nlohmann::json;
using namespace olt;

namespace {

// An entry as the publish list's JSON document holds it (what earlier versions built and dumped).
json as_json(const Published& p) {
  json j = {{"file", p.file}, {"path", p.path}, {"kind", p.kind}};
  if (!p.sensor.empty()) j["sensor"] = p.sensor;
  if (!p.observation.empty()) j["observation"] = {{"id", p.observation}, {"timestamp", p.timestamp}};
  return j;
}

std::vector<Published> read_all(const std::string& text) {
  std::vector<Published> out;
  std::istringstream stream(text);
  read_publish_list(stream, "stage/publish.json", [&](Published&& p) { out.push_back(std::move(p)); });
  return out;
}

}  // namespace

TEST_CASE("publish list: the bytes dump(1) of the JSON document writes, read back field for field") {
  const std::deque<Published> list = {
      {"a.png", "labels/cam \"1\"/a.png", "class_label", "cam \"1\" \xc3\xa9\t\\", "1305031102.175304",
       1305031102.175304},
      {"b.png", "labels/b.png", "instance_label", "", "", 0},
      {"c.json", "labels/c.json", "frame_labels", "rgbd", "0007", 0.1 + 0.2},
      {"c.png", "labels/c.png", "class_label", "rgbd", "0007", 0.1 + 0.2},  // an observation's files together
      {"e.png", "labels/e.png", "class_label", "rgbd", "0007", 0.5},        // the same id at another time
      {"d.txt", "d.txt", "", "only a sensor", "", 0},
      {"f.png", "labels/f.png", "class_label", "rgbd", "0007", 0.5},  // and again after other files
      {"g.png", "labels/g.png", "class_label", "rgbd", "0008", 0.0},
      {"h.png", "labels/h.png", "class_label", "rgbd", "0008", -0.0},  // equal to 0.0, written otherwise
  };
  json document = json::array();
  for (const auto& p : list) document.push_back(as_json(p));
  const std::string text = publish_list_text(list);
  CHECK(text == document.dump(1));
  CHECK(publish_list_text({}) == json::array().dump(1));
  // A long list comes in pieces of about a megabyte, which make the same text.
  std::deque<Published> many;
  json many_document = json::array();
  for (int i = 0; i < 20000; ++i) {
    many.push_back({"f" + std::to_string(i), "labels/cam/" + std::to_string(i) + ".png", "class_label", "cam",
                    std::to_string(i), i * 0.1});
    many_document.push_back(as_json(many.back()));
  }
  std::vector<std::string> pieces;
  publish_list_pieces(many, [&](std::string_view piece) { pieces.emplace_back(piece); });
  CHECK(pieces.size() > 1);
  std::string joined;
  for (const auto& piece : pieces) joined += piece;
  CHECK(joined == many_document.dump(1));
  // Read back as it streams (2 MB, as publishing reads a stage's list from its file).
  const std::vector<Published> many_back = read_all(joined);
  REQUIRE(many_back.size() == many.size());
  CHECK(many_back.back().path == many.back().path);
  CHECK(many_back.back().timestamp == many.back().timestamp);

  const std::vector<Published> back = read_all(text);
  REQUIRE(back.size() == list.size());
  for (size_t i = 0; i < list.size(); ++i) {
    CHECK(back[i].file == list[i].file);
    CHECK(back[i].path == list[i].path);
    CHECK(back[i].kind == list[i].kind);
    CHECK(back[i].sensor == list[i].sensor);
    CHECK(back[i].observation == list[i].observation);
    CHECK(back[i].timestamp == list[i].timestamp);  // the shortest text that reads back the same double
  }
  CHECK(read_all(json::array().dump()).empty());
  // Compact text, and members this version does not know, read as well.
  const std::vector<Published> extra =
      read_all(R"([{"path":"p","file":"f","kind":"k","size":3,"note":"n","more":{"a":[1,{"b":null}]},"flag":true,)"
               R"("observation":{"id":"1","timestamp":2,"extra":[]}}])");
  REQUIRE(extra.size() == 1);
  CHECK(extra[0].file == "f");
  CHECK(extra[0].observation == "1");
  CHECK(extra[0].timestamp == 2.0);
}

TEST_CASE("publish list: text that is not one is an error naming the file") {
  for (const std::string bad :
       {"", "{}", "[1]", R"([{"file": "f", "path": "p"}])", R"([{"file": "f", "path": 1)",
        R"([{"file": ["f"], "path": "p", "kind": "k"}])", "[[]]", "null",
        R"([{"file": "f", "path": "p", "kind": "k", "sensor": 5}])",
        R"([{"file": "f", "path": "p", "kind": "k", "observation": "x"}])",
        R"([{"file": "f", "path": "p", "kind": "k", "observation": {"id": "1"}}])",
        R"([{"file": "f", "path": "p", "kind": "k", "observation": {"timestamp": 1}}])",
        R"([{"file": "f", "path": "p", "kind": "k", "observation": {"id": 7, "timestamp": 1}}])",
        R"([{"file": "f", "path": "p", "kind": "k", "observation": {"id": "1", "timestamp": "1"}}])"}) {
    CAPTURE(bad);
    try {
      read_all(bad);
      FAIL("read without an error");
    } catch (const std::runtime_error& e) {
      CHECK(std::string(e.what()).find("stage/publish.json: not a publish list") == 0);
    }
  }
}
