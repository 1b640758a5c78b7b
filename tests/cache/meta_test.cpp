#include "cache/meta.h"

#include <catch2/catch.hpp>

using namespace olt;

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
