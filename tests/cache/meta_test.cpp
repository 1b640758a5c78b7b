#include "cache/meta.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"
#include "support/memory_file_system.h"

using namespace olt;
using namespace olt::test;

TEST_CASE("artifact metadata: read as parser events - files with their references, unknown members skipped") {
  const auto meta = read_meta(R"({
 "digest": "d1",
 "files": [
  {"path": "a.png", "sha256": ")" +
                              std::string(64, '1') + R"(", "size": 3},
  {"as": "class.png", "in": "frame-k", "path": "cam/class/1.png", "sha256": ")" +
                              std::string(64, '2') + R"(", "size": 12345678901,
   "note": {"nested": ["path", 1]}, "flag": true}
 ],
 "key": "labels-k",
 "references": ["frame-k"],
 "future": {"files": 1}
})");
  REQUIRE(meta);
  CHECK(meta->key == "labels-k");
  CHECK(meta->digest == "d1");
  REQUIRE(meta->files.size() == 2);
  CHECK(meta->files[0].path == "a.png");
  CHECK(meta->files[0].sha256 == std::string(64, '1'));
  CHECK(meta->files[0].size == 3);
  CHECK(meta->files[0].in.empty());
  CHECK(meta->files[1].in == "frame-k");
  CHECK(meta->files[1].as == "class.png");
  CHECK(meta->files[1].size == 12345678901u);
  const auto empty = read_meta(R"({"digest": "d", "files": [], "key": "k"})");
  REQUIRE(empty);
  CHECK(empty->files.empty());
}

TEST_CASE("artifact metadata: a damaged one is no metadata") {
  for (
      const std::string bad :
      {"",
       "[]",
       "\"text\"",
       "{",
       R"({"files": [], "key": "k"})",
       R"({"digest": "d", "key": "k"})",
       R"({"digest": 1, "files": [], "key": "k"})",
       R"({"digest": "d", "files": {}, "key": "k"})",
       R"({"digest": "d", "files": ["a"], "key": "k"})",
       R"({"digest": "d", "files": [[]], "key": "k"})",
       R"({"digest": "d", "files": [{"path": "a", "sha256": "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"}], "key": "k"})",
       R"({"digest": "d", "files": [{"path": "a", "size": 1}], "key": "k"})",
       R"({"digest": "d", "files": [{"path": "a", "sha256": "s", "size": 1}], "key": "k"})",  // no digest
       R"({"digest": "d", "files": [{"path": "a", "sha256": "AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA", "size": 1}], "key": "k"})",
       R"({"digest": "d", "files": [{"path": "a", "sha256": "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa", "size": -1}], "key": "k"})",
       R"({"digest": "d", "files": [{"path": "a", "sha256": "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa", "size": 1.5}], "key": "k"})",
       R"({"digest": "d", "files": [{"path": 7, "sha256": "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa", "size": 1}], "key": "k"})",
       R"({"digest": "d", "files": [{"path": "a", "sha256": "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa", "size": 1, "in": ["k"]}], "key": "k"})",
       R"({"digest": "d", "files": [], "key": "k"} trailing)",
       R"({"digest": "d", "files": [{"path": "a", "sha256": "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa", "size": 1}], "files": [], "key": "k"})"}) {
    CAPTURE(bad);
    CHECK_FALSE(read_meta(bad));
  }
}

TEST_CASE("metadata read from its file as it streams: the same list, made of its size") {
  Place place(GENERATE(true, false));
  std::string text = "{\n \"digest\": \"d\",\n \"files\": [";
  const std::string digest(64, 'a');
  for (int i = 0; i < 3000; ++i)  // ~400 KB: "sha256" falls across the stream's 64 KB pieces
    text += std::string(i ? "," : "") + "\n  {\n   \"path\": \"cam/class/" + std::to_string(i) +
            ".png\",\n   \"sha256\": \"" + digest + "\",\n   \"size\": " + std::to_string(i) + "\n  }";
  text += "\n ],\n \"key\": \"k\"\n}";
  place.files().write(place.root() / ".artifact.json", text);
  const auto meta = read_meta_file(place.files(), place.root() / ".artifact.json");
  REQUIRE(meta);
  CHECK(meta->files.size() == 3000);
  CHECK(meta->files.capacity() == 3000);                 // counted first, not grown by doubling
  CHECK(meta->files[2999].path == "cam/class/999.png");  // sorted by path, as find needs them
  REQUIRE(meta->files.find("cam/class/2999.png"));
  CHECK(meta->files.find("cam/class/2999.png")->size == 2999);
  CHECK(read_meta(text)->files.size() == 3000);
  CHECK_THROWS_AS(read_meta_file(place.files(), place.root() / "missing.json"), InputError);  // a miss to Store::find
}
