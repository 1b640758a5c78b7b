// The content store: commit and find, digests that follow content, damaged entries treated as misses.
#include "olt/cache/store.h"

#include <catch2/catch.hpp>

#include "olt/core/fs.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

Artifact store_one(const Store& store, const std::string& key, const std::string& content) {
  const fs::path dir = store.begin(key);
  write_file_atomic(dir / "a.txt", content);
  write_file_atomic(dir / "sub/b.txt", "b");
  return store.commit(key, dir);
}

}  // namespace

TEST_CASE("store: committed artifacts are found with their files and a digest of their content") {
  TempDir dir;
  const Store store(dir.path());
  CHECK_FALSE(store.find("k1"));
  const Artifact a = store_one(store, "k1", "hello");
  REQUIRE(store.find("k1"));
  CHECK(store.find("k1")->digest == a.digest);
  REQUIRE(a.files.size() == 2);
  CHECK(a.files[1].path == "sub/b.txt");
  CHECK(read_file(a.dir / "a.txt") == "hello");
  // same content under another key: same digest; other content: another digest
  CHECK(store_one(store, "k2", "hello").digest == a.digest);
  CHECK(store_one(store, "k3", "hello!").digest != a.digest);
  // nothing is left in the temporary area
  CHECK(fs::is_empty(dir / "tmp"));
}

TEST_CASE("store: a damaged entry is a miss and the next commit replaces it") {
  TempDir dir;
  const Store store(dir.path());
  const Artifact a = store_one(store, "k1", "hello");
  write_text(a.dir / "a.txt", "he");  // truncated
  CHECK_FALSE(store.find("k1"));
  const Artifact again = store_one(store, "k1", "hello");
  REQUIRE(store.find("k1"));
  CHECK(read_file(again.dir / "a.txt") == "hello");
  write_text(a.dir / ".artifact.json", "{not json");
  CHECK_FALSE(store.find("k1"));
}

TEST_CASE("store: records and log lines carry their format; a record of another format is absent, not an error") {
  TempDir dir;
  const Store store(dir.path());
  const nlohmann::json record = {{"kind", "poses"}, {"version", 9}};
  store.save_record("job1", "poses", record);
  REQUIRE(store.record("job1", "poses"));
  CHECK(*store.record("job1", "poses") == record);
  CHECK(nlohmann::json::parse(read_file(dir.path() / "records/job1/poses.json"))["format"] == kRecordFormat);
  REQUIRE(store.records().size() == 1);

  // A newer OLT's record, an older one's (no wrapper), and bytes that are no JSON: all read as absent.
  write_file_atomic(dir.path() / "records/job1/newer.json",
                    nlohmann::json({{"format", kRecordFormat + 1}, {"record", record}}).dump());
  write_file_atomic(dir.path() / "records/job1/older.json", record.dump());
  write_file_atomic(dir.path() / "records/job2/broken.json", "{not json");
  CHECK_FALSE(store.record("job1", "newer"));
  CHECK_FALSE(store.record("job1", "older"));
  CHECK_FALSE(store.record("job2", "broken"));
  CHECK_FALSE(store.record("job3", "never"));
  CHECK(store.records().size() == 1);

  store.log({{"stage", "poses"}, {"reason", "never run"}});
  const auto line = nlohmann::json::parse(read_file(dir.path() / "log.jsonl"));
  CHECK(line["format"] == kRecordFormat);
  CHECK(line["stage"] == "poses");
}
