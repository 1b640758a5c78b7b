// The content store: commit and find, digests that follow content, damaged entries treated as misses.
// Most cases run on the real file system and on the memory one: both give the same answers.
#include "olt/cache/store.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "olt/core/error.h"
#include "olt/core/hash.h"
#include "olt/core/process_memory.h"
#include "support/keeping_memory.h"
#include "support/memory_file_system.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

Artifact store_one(const Store& store, const std::string& key, const std::string& content) {
  const fs::path dir = store.begin(key);
  store.files().write(dir / "a.txt", content);
  store.files().write(dir / "sub/b.txt", "b");
  return store.commit(key, dir);
}

// `from`'s file `file`, referred to as "from_<key>/<file>".
ArtifactFile referred_from(const Artifact& from, const std::string& file) {
  return {"from_" + from.key + "/" + file, from.file(file)->sha256, from.file(file)->size, from.key, file};
}

}  // namespace

TEST_CASE("store: committed artifacts are found with their files and a digest of their content") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  CHECK_FALSE(store.find("k1"));
  const Artifact a = store_one(store, "k1", "hello");
  REQUIRE(store.find("k1"));
  CHECK(store.find("k1")->digest == a.digest);
  REQUIRE(a.files.size() == 2);
  CHECK(a.files[1].path == "sub/b.txt");
  CHECK(a.files[0].sha256 == "2cf24dba5fb0a30e26e83b2ac5b9e29e1b161e5c1fa7425e73043362938b9824");  // sha256 "hello"
  CHECK(place.files().read(a.dir / "a.txt") == "hello");
  // same content under another key: same digest; other content: another digest
  CHECK(store_one(store, "k2", "hello").digest == a.digest);
  CHECK(store_one(store, "k3", "hello!").digest != a.digest);
  // nothing is left in the temporary area
  CHECK(place.files().list(place.root() / "tmp").empty());
}

TEST_CASE("store: a damaged entry is a miss and the next commit replaces it") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  const Artifact a = store_one(store, "k1", "hello");
  place.files().write(a.dir / "a.txt", "he");  // truncated
  CHECK_FALSE(store.find("k1"));
  const Artifact again = store_one(store, "k1", "hello");
  REQUIRE(store.find("k1"));
  CHECK(place.files().read(again.dir / "a.txt") == "hello");
  place.files().write(a.dir / ".artifact.json", "{not json");
  CHECK_FALSE(store.find("k1"));
  // verify names what is damaged
  const Store::Verification v = store.verify();
  CHECK(v.artifacts == 1);
  REQUIRE(v.problems.size() == 1);
  CHECK(v.problems[0].key == "k1");
  // A file name longer than a list holds (64 KB): a miss and a problem, not a crash.
  const std::string long_name(70000, 'x');
  place.files().write(a.dir / ".artifact.json", R"({"digest": "d", "files": [{"path": ")" + long_name +
                                                    R"(", "sha256": ")" + std::string(64, 'a') +
                                                    R"(", "size": 1}], "key": "k1"})");
  CHECK_FALSE(store.find("k1"));
  CHECK(store.verify().problems.size() == 1);
}

TEST_CASE("store: records and log lines carry their format - a record of another format is absent, not an error") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const Store store(place.root(), files);
  const nlohmann::json record = {{"kind", "poses"}, {"version", 9}};
  store.save_record("job1", "poses", record);
  REQUIRE(store.record("job1", "poses"));
  CHECK(*store.record("job1", "poses") == record);
  CHECK(nlohmann::json::parse(files.read(place.root() / "records/job1/poses.json"))["format"] == kRecordFormat);
  REQUIRE(store.records().size() == 1);

  // A newer OLT's record, an older one's (no wrapper), and bytes that are no JSON: all read as absent.
  files.write(place.root() / "records/job1/newer.json",
              nlohmann::json({{"format", kRecordFormat + 1}, {"record", record}}).dump());
  files.write(place.root() / "records/job1/older.json", record.dump());
  files.write(place.root() / "records/job2/broken.json", "{not json");
  CHECK_FALSE(store.record("job1", "newer"));
  CHECK_FALSE(store.record("job1", "older"));
  CHECK_FALSE(store.record("job2", "broken"));
  CHECK_FALSE(store.record("job3", "never"));
  CHECK(store.records().size() == 1);

  store.log({{"stage", "poses"}, {"reason", "never run"}});
  store.log({{"stage", "labels"}});
  const std::string log = files.read(place.root() / "log.jsonl");
  const auto line = nlohmann::json::parse(log.substr(0, log.find('\n')));
  CHECK(line["format"] == kRecordFormat);
  CHECK(line["stage"] == "poses");
  CHECK(std::count(log.begin(), log.end(), '\n') == 2);
}

TEST_CASE("store: garbage collection keeps what the roots reach through references, removes the rest") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  store.mark();
  store_one(store, "k1", "one");
  const Artifact two = store_one(store, "k2", "two");
  const uint64_t meta_bytes = store.files().stat(two.dir / ".artifact.json").size;
  const fs::path dir = store.begin("k3");
  store.files().write(dir / "c.txt", "three");
  store.commit("k3", dir, {referred_from(store.find("k1").value(), "a.txt")});
  const Store::Collection c = store.collect_garbage({"k3"}, 1e9);
  CHECK(c.kept == 2);
  CHECK(c.removed == 1);
  CHECK(c.bytes_freed == 4 + meta_bytes);  // "two", "b" and the metadata
  CHECK(store.find("k1"));
  CHECK_FALSE(store.find("k2"));
  CHECK(store.find("k3"));
}

TEST_CASE("store: a commit that meets a full disk leaves no entry and no temporary folder") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const fs::path dir = store.begin("k1");
  files.write(dir / "a.txt", "hello");
  files.fail_writes_after(0);  // the metadata file does not fit
  try {
    store.commit("k1", dir);
    FAIL("the commit should fail");
  } catch (const FileSystemError& e) {
    CHECK_THAT(e.what(), Catch::Contains("No space left on device"));
  }
  store.discard(dir);
  files.fail_writes_after(-1);
  CHECK_FALSE(store.find("k1"));
  CHECK(files.list("/cache/tmp").empty());
}

TEST_CASE("input digests are remembered by size, time and identity - an edited file is hashed again") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path input = place.root() / "input.txt", memo = place.root() / "memo.json";
  files.write(input, "hello");
  FileDigests digests(memo, files);
  CHECK(digests.digest(input) == "2cf24dba5fb0a30e26e83b2ac5b9e29e1b161e5c1fa7425e73043362938b9824");
  digests.save();
  CHECK(files.stat(memo).is_file());
  files.write(input, "hello!");  // a new size: hashed again
  FileDigests again(memo, files);
  CHECK(again.digest(input) == "ce06092fb948d9ffac7d1a376e404b26b7575bcc11ee05a4615fef4fec3a308b");
  CHECK_THROWS_AS(again.digest(place.root() / "missing.txt"), InputError);
}

TEST_CASE(
    "store: gc removes nothing from a folder that is not a cache, nor through a link, nor what OLT did not name") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root() / "cache";
  const Store store(root, files);
  store_one(store, "k1", "one");
  try {
    store.collect_garbage({}, 0);
    FAIL("no marker");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("not an OLT cache"));
  }
  CHECK(store.find("k1"));

  store.mark();
  // objects/zz is a link to someone's folder shaped like a cache entry; tmp/ holds a file of theirs.
  files.write(place.root() / "precious/zzkey/.artifact.json", "{}");
  files.write(place.root() / "precious/zzkey/data.txt", "keep");
  place.symlink(place.root() / "precious", root / "objects/zz");
  files.write(root / "tmp/notes.txt", "keep too");
  const Store::Collection c = store.collect_garbage({}, 0);
  CHECK(c.removed == 1);  // k1
  CHECK_FALSE(store.find("k1"));
  CHECK(files.read(place.root() / "precious/zzkey/data.txt") == "keep");
  CHECK(files.read(root / "tmp/notes.txt") == "keep too");
}

TEST_CASE("store: dropping a damaged entry removes it and the entries it refers to, nothing else") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  store_one(store, "k1", "one");
  const fs::path dir = store.begin("k2");
  files.write(dir / "x.txt", "x");
  const Artifact two = store.commit("k2", dir, {referred_from(store.find("k1").value(), "a.txt")});
  // A damaged entry may name anything: only folders under objects/ are removed.
  auto meta = nlohmann::json::parse(files.read(two.dir / ".artifact.json"));
  meta["references"].push_back("../../precious");
  files.write(two.dir / ".artifact.json", meta.dump());
  files.write("/precious/file", "keep");
  store_one(store, "k3", "three");
  store.drop("k2");
  CHECK_FALSE(store.find("k2"));
  CHECK_FALSE(store.find("k1"));
  CHECK(store.find("k3"));
  CHECK(files.read("/precious/file") == "keep");
}

TEST_CASE("store: a file referred to from another entry is listed, not copied, read where it is, and checked there") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  const Artifact one = store_one(store, "k1", "one");
  fs::path dir = store.begin("k2");
  store.files().write(dir / "c.txt", "two");
  const Artifact two = store.commit("k2", dir, {referred_from(one, "a.txt")});
  // The same files written out: the same digest (digests follow content, not where bytes are).
  dir = store.begin("k3");
  store.files().write(dir / "c.txt", "two");
  store.files().write(dir / "from_k1/a.txt", "one");
  CHECK(store.commit("k3", dir).digest == two.digest);

  const auto found = store.find("k2");
  REQUIRE(found);
  REQUIRE(found->file("from_k1/a.txt"));
  CHECK(found->path("from_k1/a.txt") == one.dir / "a.txt");
  CHECK(found->path("c.txt") == found->dir / "c.txt");
  CHECK(store.files().read(found->path("from_k1/a.txt")) == "one");
  CHECK_FALSE(store.files().stat(found->dir / "from_k1/a.txt").exists());  // no copy, no link
  CHECK(store.verify().problems.empty());
  const std::string meta = store.files().read(two.dir / ".artifact.json");  // written in pieces
  CHECK(meta == nlohmann::json::parse(meta).dump(1));
  const Artifact empty = store.commit("k4", store.begin("k4"));
  const std::string empty_meta = store.files().read(empty.dir / ".artifact.json");
  CHECK(empty_meta == nlohmann::json::parse(empty_meta).dump(1));

  // The referred bytes changed: verify names both entries; changed in size, the referring entry is a miss.
  store.files().write(one.dir / "a.txt", "0ne");
  const auto problems = store.verify().problems;
  REQUIRE(problems.size() == 2);
  CHECK(problems[0].key == "k1");
  CHECK(problems[1].key == "k2");
  CHECK_THAT(problems[1].message, Catch::Contains("from_k1/a.txt") && Catch::Contains("sha256 differs"));
  store.files().write(one.dir / "a.txt", "one, longer");
  CHECK_FALSE(store.find("k2"));
  CHECK(store.find("k3"));
}

TEST_CASE("store: an entry found as listed is its metadata's list, its files not looked for - find checks them") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  const Artifact one = store_one(store, "k1", "one");
  const fs::path dir = store.begin("k2");
  store.files().write(dir / "c.txt", "two");
  const Artifact two = store.commit("k2", dir, {referred_from(one, "a.txt")});
  store.files().remove(one.dir / "a.txt");  // the file k2 refers to, gone
  CHECK_FALSE(store.find("k2"));
  const auto listed = store.find_unchecked("k2");
  REQUIRE(listed);
  CHECK(listed->digest == two.digest);
  REQUIRE(listed->files.size() == 2);
  CHECK(listed->files[0].path == "c.txt");
  CHECK(listed->path(listed->files[1]) == one.dir / "a.txt");
  CHECK_FALSE(store.find_unchecked("k9"));
}

TEST_CASE("store: own files described as hashed when written are listed with that digest, unread - the rest hashed") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  const Artifact one = store_one(store, "k0", "one");
  const fs::path dir = store.begin("k1");
  for (const std::string file : {"a.txt", "a-b/c.txt", "a/b/c.txt", "b.txt", "z.txt"})
    store.files().write(dir / file, file);
  // A digest the bytes do not have shows the store took the described one rather than reading the
  // file; c.txt is described but was never written: not listed. Subfolders sort between names
  // ("a-b/..." < "a.txt" < "a/..."), and a referred file comes in the same list.
  const Digest described(std::string(64, 'f'));
  const Artifact a = store.commit("k1", dir,
                                  {{"z.txt", described, 5, "", ""},
                                   {"a/b/c.txt", described, 9, "", ""},
                                   referred_from(one, "a.txt"),
                                   {"c.txt", described, 1, "", ""},
                                   {"a-b/c.txt", described, 9, "", ""}});
  REQUIRE(a.files.size() == 6);
  CHECK(a.files[0].path == "a-b/c.txt");
  CHECK(a.files[0].sha256 == described);
  CHECK(a.files[1].path == "a.txt");
  CHECK(a.files[1].sha256 == sha256_hex("a.txt"));  // not described: hashed
  CHECK(a.files[2].path == "a/b/c.txt");
  CHECK(a.files[2].sha256 == described);
  CHECK(a.files[3].path == "b.txt");
  CHECK(a.files[3].sha256 == sha256_hex("b.txt"));
  CHECK(a.files[3].size == 5);
  CHECK(a.files[4].path == "from_k0/a.txt");
  CHECK(a.files[4].in == "k0");
  CHECK(a.files[5].path == "z.txt");
  CHECK(a.files[5].sha256 == described);
  // What `cache verify` is for: listed bytes that are not the file's are found there (the first named).
  const auto problems = store.verify().problems;
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].key == "k1");
  CHECK_THAT(problems[0].message, Catch::Contains("a-b/c.txt") && Catch::Contains("sha256 differs"));
}

TEST_CASE("store: in olt watch an entry found before is that entry while its metadata is the same file") {
  TempDir temp;
  const Store store(temp.path());
  keep_in_memory(64 << 20);  // as olt watch does
  const Artifact a = store_one(store, "k1", "hello");
  REQUIRE(store.find("k1"));
  // Found again without its files checked again: a file damaged inside it goes unnoticed here (the
  // cost an edit cycle saves: 30,000 stats for a 10,000-frame recording's images) ...
  real_file_system().write(a.dir / "a.txt", "he");
  CHECK(store.find("k1"));
  // ... and is noticed by olt run, which keeps nothing.
  keep_in_memory(0);
  CHECK_FALSE(store.find("k1"));
  keep_in_memory(64 << 20);
  // An entry committed anew under the key (another metadata file) is read anew.
  store.drop("k1");
  CHECK_FALSE(store.find("k1"));
  const Artifact again = store_one(store, "k1", "other");
  REQUIRE(store.find("k1"));
  CHECK(store.find("k1")->digest == again.digest);
  CHECK(again.digest != a.digest);
  // The same bytes in another metadata file (this process knew the entry it committed): read anew.
  real_file_system().write_atomic(again.dir / ".artifact.json", real_file_system().read(again.dir / ".artifact.json"));
  REQUIRE(store.find("k1"));
  CHECK(store.find("k1")->digest == again.digest);
  // Its metadata rewritten (damaged): read anew, a miss.
  real_file_system().write(again.dir / ".artifact.json", "{not json");
  CHECK_FALSE(store.find("k1"));
  keep_in_memory(0);
}

TEST_CASE("store: an entry forgotten in olt watch is found again by checking its files") {
  TempDir temp;
  const Store store(temp.path());
  const KeepingMemory keeping;  // as olt watch does
  const Artifact a = store_one(store, "k1", "hello");
  const Artifact b = store_one(store, "k2", "world");
  real_file_system().write(a.dir / "a.txt", "he");  // damaged: unnoticed while remembered
  real_file_system().write(b.dir / "a.txt", "wo");
  REQUIRE(store.find("k1"));
  store.forget("k1");
  CHECK_FALSE(store.find("k1"));  // its files checked: the damage found
  CHECK(store.find("k2"));        // the other one still remembered
  store.forget("never-made");     // nothing to forget: nothing happens
  CHECK(store.find("k2"));
}

TEST_CASE("store: in olt watch the entries a stage used the run before and not now are forgotten, and named") {
  TempDir temp;
  const Store store(temp.path());
  const KeepingMemory keeping;  // as olt watch does
  std::map<std::string, Artifact> made;
  for (const std::string key : {"k1", "k2", "k3", "k4"}) made.emplace(key, store_one(store, key, "hello"));
  CHECK(store.forget_unused("frames:job:labels", {"k1", "k2", "k3"}).empty());  // no run before
  // The next run used k2 and k4: k1 and k3 forgotten (damaged, they are checked and missed), k2 and
  // k4 still remembered (damaged, found unchecked).
  CHECK(store.forget_unused("frames:job:labels", {"k4", "k2"}) == std::vector<std::string>{"k1", "k3"});
  for (const auto& [key, artifact] : made) real_file_system().write(artifact.dir / "a.txt", "he");
  CHECK_FALSE(store.find("k1"));
  CHECK(store.find("k2"));
  CHECK_FALSE(store.find("k3"));
  CHECK(store.find("k4"));
  // Another name keeps its own list: its first run forgets nothing, and the next run under the first
  // name compares with that name's last run only.
  CHECK(store.forget_unused("pieces:job:report", {"k2"}).empty());
  CHECK(store.forget_unused("frames:job:labels", {"k2"}) == std::vector<std::string>{"k4"});
}

TEST_CASE("store: in olt watch an entry this process committed is found by one stat, as it was listed, nothing read") {
  // On the memory file system alone: it counts what finding an entry costs (its metadata read, its
  // files looked at).
  struct CountingFileSystem : MemoryFileSystem {
    mutable std::atomic<int> reads = 0, stats = 0;
    std::string read(const fs::path& file) const override {
      ++reads;
      return MemoryFileSystem::read(file);
    }
    FileStat stat(const fs::path& path, bool follow_link) const override {
      ++stats;
      return MemoryFileSystem::stat(path, follow_link);
    }
  } files;
  const Store store("/cache", files);
  const KeepingMemory keeping;  // as olt watch does
  const auto found_unread = [&](const std::string& key) {
    files.reads = 0;
    files.stats = 0;
    const std::optional<Artifact> found = store.find(key);
    CHECK(files.reads == 0);
    CHECK(files.stats == 1);  // its metadata file, still the one committed
    return found;
  };
  // An entry with a file of its own and one referred to in another entry.
  const Artifact from = store_one(store, "k0", "hello");
  fs::path dir = store.begin("k1");
  files.write(dir / "own.txt", "own");
  const Artifact made = store.commit("k1", dir, {referred_from(from, "a.txt")});
  const Artifact listed = store.find_unchecked("k1").value();  // its metadata as written
  CHECK(made.digest == listed.digest);
  const std::optional<Artifact> found = found_unread("k1");
  REQUIRE(found);
  CHECK(found->digest == listed.digest);
  CHECK(found->dir == listed.dir);
  REQUIRE(found->files.size() == 2);
  REQUIRE(listed.files.size() == 2);
  for (size_t i = 0; i < listed.files.size(); ++i) {
    CHECK(found->files[i].path == listed.files[i].path);
    CHECK(found->files[i].sha256 == listed.files[i].sha256);
    CHECK(found->files[i].size == listed.files[i].size);
    CHECK(found->files[i].in == listed.files[i].in);
    CHECK(found->files[i].as == listed.files[i].as);
  }
  CHECK(found->file("from_k0/a.txt")->in == "k0");
  // Another writer's entry already in place under the key: theirs is what is known.
  const Store other("/cache", files);
  const Artifact theirs = store_one(other, "k2", "theirs");
  const Artifact ours = store_one(store, "k2", "ours");
  CHECK(ours.digest == theirs.digest);
  REQUIRE(found_unread("k2"));
  CHECK(store.find("k2")->digest == theirs.digest);
  // A damaged entry replaced: the new one is known.
  files.write(store.find("k2")->dir / ".artifact.json", "{not json");
  CHECK_FALSE(store.find("k2"));
  const Artifact replaced = store_one(store, "k2", "again");
  REQUIRE(found_unread("k2"));
  CHECK(store.find("k2")->digest == replaced.digest);
  CHECK(replaced.digest != theirs.digest);
  // Removed (as a run whose sync failed removes what it committed): not found (this also held before
  // committed entries were known).
  store.remove("k2");
  CHECK_FALSE(store.find("k2"));
}

TEST_CASE(
    "store: the keys committed are taken once - one another writer committed is not listed, removing one leaves the "
    "rest") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  store_one(store, "k1", "one");
  store_one(store, "k2", "two");
  CHECK(store.take_committed() == std::vector<std::string>{"k1", "k2"});
  CHECK(store.take_committed().empty());
  // OLT's own keys (a digest's hex, after a name or not) are held as digests, and come back as the same text.
  const std::string key = sha256_hex("three"), frame = "frame-" + sha256_hex("3");
  store_one(store, key, "three");
  store_one(store, frame, "3");
  store_one(store, "k4", "four");
  const std::vector<std::string> taken = store.take_committed();
  CHECK(std::set<std::string>(taken.begin(), taken.end()) == std::set<std::string>{key, frame, "k4"});
  store_one(store, "k5", "five");
  store.clear_committed();  // durable: nothing to remove
  CHECK(store.take_committed().empty());
  // Another writer's entry already in place under the key: theirs is kept, and it is not ours to list.
  const Store other("/cache", files);
  const fs::path dir = other.begin("k1");
  files.write(dir / "a.txt", "one");
  other.commit("k1", dir);
  CHECK(other.take_committed().empty());
  // Removed alone: an entry it refers to stays.
  const fs::path three = store.begin("k3");
  files.write(three / "x.txt", "x");
  store.commit("k3", three, {referred_from(store.find("k1").value(), "a.txt")});
  store.remove("k3");
  CHECK_FALSE(store.find("k3"));
  CHECK(store.find("k1"));
  CHECK(store.find("k2"));
}
