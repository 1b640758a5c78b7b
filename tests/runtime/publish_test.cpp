// Publishing on a file system in memory: the output gets each stage's listed files and a manifest
// with their digests; an unchanged file is not copied again; a file no stage lists any more is
// removed; bad publish lists are refused before anything is written. Publishes killed midway are in
// tests/runtime/kill_test.cpp (a real process killed at each of publishing's fault points).
#include "olt/runtime/publish.h"

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>

#include "olt/core/error.h"
#include "olt/core/hash.h"
#include "olt/core/process_memory.h"
#include "olt/core/run_memory.h"
#include "olt/runtime/runner.h"
#include "runtime/artifact_folder.h"
#include "runtime/manifest.h"
#include "runtime/pending_publish.h"
#include "runtime/publish_list.h"
#include "support/keeping_memory.h"
#include "support/memory_file_system.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;
using nlohmann::json;

namespace {

// A stage's artifact in the store: `files` (name -> bytes), each published under "stage/name".
Artifact stage_artifact(const Store& store, const std::string& key, const std::map<std::string, std::string>& files,
                        const std::string& folder = "") {
  const fs::path dir = store.begin(key);
  ArtifactFolder out(dir, store.files());
  for (const auto& [name, bytes] : files) {
    out.write(name, bytes);
    out.publish(name, (folder.empty() ? key : folder) + "/" + name, "test");
  }
  std::string list;
  out.publish_list([&](std::string_view piece) { list += piece; });
  out.write("publish.json", list);
  return store.commit(key, dir);
}

}  // namespace

TEST_CASE(
    "publish: listed files and a sorted manifest with their digests - nothing written when nothing changed, unchanged "
    "files not copied again") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const std::vector<std::pair<std::string, Artifact>> artifacts = {
      {"poses", stage_artifact(store, "poses", {{"trajectory.txt", "1 2 3"}})},
      {"labels", stage_artifact(store, "labels", {{"a.png", "A"}, {"b.png", "B"}})}};
  publish_outputs("/out", artifacts, files);
  const json manifest = json::parse(files.read("/out/manifest.json"));
  CHECK(files.read("/out/manifest.json") == manifest.dump(1) + "\n");
  REQUIRE(manifest["files"].size() == 3);
  CHECK(manifest["files"][0]["path"] == "labels/a.png");
  CHECK(manifest["files"][0]["sha256"] == sha256_hex("A"));
  CHECK(manifest["files"][0]["stage"] == "labels");
  CHECK(manifest["files"][2]["path"] == "poses/trajectory.txt");
  CHECK(files.read("/out/labels/b.png") == "B");

  // Again: nothing to do, nothing written (not a link, not the manifest); the same files.
  const uint64_t identity = files.stat("/out/labels/b.png").identity;
  const int64_t writes = files.writes();
  publish_outputs("/out", artifacts, files);
  CHECK(json::parse(files.read("/out/manifest.json")) == manifest);
  CHECK(files.writes() == writes);
  CHECK(files.stat("/out/labels/b.png").identity == identity);
  CHECK(files.list("/").size() == 2);  // cache and out: nothing left beside the output

  // A listed file removed by hand: published again, the others kept as the same files (hard links
  // to the last output's), not copied.
  files.remove("/out/labels/a.png");
  publish_outputs("/out", artifacts, files);
  CHECK(files.read("/out/labels/a.png") == "A");
  CHECK(files.stat("/out/labels/b.png").identity == identity);
  CHECK(files.list("/").size() == 2);

  // labels now lists a.png only (under labels2/): b.png and a.png leave labels/
  publish_outputs("/out", {artifacts[0], {"labels", stage_artifact(store, "labels2", {{"a.png", "A"}})}}, files);
  CHECK_FALSE(files.stat("/out/labels/b.png").exists());
  CHECK(files.stat("/out/labels2/a.png").is_file());
}

TEST_CASE("publish: two stages writing one path, or a path leaving the output, are refused before any write") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const Artifact a = stage_artifact(store, "same", {{"x.txt", "1"}});
  const int64_t writes = files.writes();
  CHECK_THROWS_AS(publish_outputs("/out", {{"one", a}, {"two", a}}, files), InputError);

  const fs::path dir = store.begin("escape");
  files.write(dir / "x.txt", "1");
  Published outside;
  outside.file = "x.txt";
  outside.path = "../x.txt";
  files.write(dir / "publish.json", publish_list_text({outside}));
  const Artifact escaping = store.commit("escape", dir);
  const int64_t before = files.writes();
  try {
    publish_outputs("/out", {{"bad", escaping}}, files);
    FAIL("the path leaves the output");
  } catch (const StageFailure& e) {
    CHECK_THAT(e.what(), Catch::Contains("'../x.txt' would leave the output folder"));
  }
  CHECK(files.writes() == before);
  CHECK(before > writes);
  CHECK_FALSE(files.stat("/out").exists());
}

TEST_CASE("publish: nothing is written or removed through a symbolic link inside the output") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const Artifact labels = stage_artifact(store, "labels", {{"a.png", "A"}, {"b.png", "B"}});
  publish_outputs("/out", {{"labels", labels}}, files);
  // Someone replaces labels/ with a link to a folder holding files of the same names.
  files.write("/elsewhere/a.png", "old");
  files.write("/elsewhere/b.png", "B");
  files.remove("/out/labels");
  files.symlink("/elsewhere", "/out/labels");

  // A file to publish there is an error naming the path; nothing is written through the link.
  try {
    publish_outputs("/out", {{"labels", labels}}, files);
    FAIL("the link is on the way");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("/out/labels/a.png") && Catch::Contains("symbolic link"));
  }
  CHECK(files.read("/elsewhere/a.png") == "old");

  // labels/ leaves the output: the files the link reaches stay where they are (b.png holds the bytes
  // the last manifest listed for labels/b.png, and is not removed); the link itself is not carried.
  publish_outputs("/out", {{"poses", stage_artifact(store, "poses", {{"t.txt", "T"}})}}, files);
  CHECK(files.read("/elsewhere/a.png") == "old");
  CHECK(files.read("/elsewhere/b.png") == "B");
  CHECK(files.read("/out/poses/t.txt") == "T");
}

TEST_CASE("publish: a file someone edited stays when it leaves the manifest") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  publish_outputs("/out", {{"labels", stage_artifact(store, "labels", {{"a.png", "A"}, {"b.png", "B"}})}}, files);
  files.write("/out/labels/b.png", "edited by hand");
  publish_outputs("/out", {{"labels", stage_artifact(store, "fewer", {{"a.png", "A"}})}}, files);
  CHECK(files.read("/out/labels/b.png") == "edited by hand");
  CHECK_FALSE(files.stat("/out/labels/a.png").exists());  // it held the listed bytes: removed
}

TEST_CASE("publish: cache bytes that are not those recorded are refused, naming the file - nothing is published") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const Artifact labels = stage_artifact(store, "labels", {{"a.png", "AAAA"}});
  files.write(labels.dir / "a.png", "AAAB");  // one byte changed, same size
  try {
    publish_outputs("/out", {{"labels", labels}}, files);
    FAIL("the entry is damaged");
  } catch (const DamagedArtifact& e) {
    CHECK(e.key() == "labels");
    CHECK(e.stage() == "labels");
    CHECK_THAT(e.what(), Catch::Contains("/a.png") && Catch::Contains("does not hold the bytes recorded"));
  }
  CHECK(files.files_below("/out").empty());
}

TEST_CASE("publish: all or nothing - a disk that fills up at any write leaves the last output whole") {
  int failed = 0;
  for (int64_t n = 0;; ++n) {
    MemoryFileSystem files;
    const Store store("/cache", files);
    publish_outputs("/out", {{"labels", stage_artifact(store, "labels", {{"a.png", "A"}, {"b.png", "B"}})}}, files);
    files.write("/out/notes.txt", "mine");
    std::string before;
    for (const auto& path : files.files_below("/out")) before += path + "=" + files.read("/out/" + path) + "\n";
    const Artifact next = stage_artifact(store, "next", {{"a.png", "A2"}, {"c.png", "C"}});
    files.fail_writes_after(n);
    try {
      publish_outputs("/out", {{"labels", next}}, files);
    } catch (const FileSystemError& e) {
      ++failed;
      INFO("disk full after " << n << " writes: " << e.what());
      std::string after;
      for (const auto& path : files.files_below("/out")) after += path + "=" + files.read("/out/" + path) + "\n";
      CHECK(after == before);
      CHECK(files.list("/").size() == 2);  // no staged folder left
      continue;
    }
    // Enough room: the new output, the user's file kept, b.png gone.
    CHECK(files.read("/out/next/a.png") == "A2");
    CHECK(files.read("/out/notes.txt") == "mine");
    CHECK_FALSE(files.stat("/out/labels/b.png").exists());
    break;
  }
  CHECK(failed >= 4);
}

TEST_CASE("publish: two jobs publishing into one output leave the last one's files, agreeing with its manifest") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  publish_outputs("/out", {{"labels", stage_artifact(store, "first", {{"a.png", "A"}, {"b.png", "B"}})}}, files);
  publish_outputs("/out", {{"labels", stage_artifact(store, "second", {{"c.png", "C"}})}}, files);
  const json manifest = json::parse(files.read("/out/manifest.json"));
  std::vector<std::string> listed;
  for (const auto& f : manifest["files"]) {
    listed.push_back(f["path"]);
    CHECK(files.sha256("/out/" + f["path"].get<std::string>()) == f["sha256"]);
  }
  std::vector<std::string> present = files.files_below("/out");
  present.erase(std::remove(present.begin(), present.end(), "manifest.json"), present.end());
  CHECK(present == listed);
  CHECK(listed == std::vector<std::string>{"second/c.png"});
}

TEST_CASE("publish: an edit writes only the files it changed, staged inside the output - folders left empty go") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  publish_outputs("/out",
                  {{"labels", stage_artifact(store, "labels", {{"a.png", "A"}, {"b.png", "B"}, {"c.png", "C"}})},
                   {"frames", stage_artifact(store, "frames", {{"x.json", "X"}}, "frames/cam")}},
                  files);
  files.write("/out/notes.txt", "mine");
  const uint64_t a = files.stat("/out/labels/a.png").identity, c = files.stat("/out/labels/c.png").identity;
  const Artifact edited =
      stage_artifact(store, "labels_v2", {{"a.png", "A"}, {"b.png", "B2"}, {"c.png", "C"}}, "labels");
  const int64_t writes = files.writes();
  publish_outputs("/out", {{"labels", edited}}, files);
  CHECK(files.writes() - writes == 3);  // b.png, the manifest, the journal of the changes
  CHECK(files.read("/out/labels/b.png") == "B2");
  CHECK(files.stat("/out/labels/a.png").identity == a);  // the same files, untouched
  CHECK(files.stat("/out/labels/c.png").identity == c);
  CHECK(files.read("/out/notes.txt") == "mine");
  CHECK(files.list("/out") == std::vector<std::string>{"labels", "manifest.json", "notes.txt"});  // frames/ went
  CHECK(json::parse(files.read("/out/manifest.json"))["files"].size() == 3);
  CHECK(files.list("/").size() == 2);  // nothing beside the output
}

TEST_CASE("publish: a folder where a file goes is an error naming it, before anything changes") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  publish_outputs("/out", {{"labels", stage_artifact(store, "labels", {{"a.png", "A"}})}}, files);
  files.make_folders("/out/labels/b.png/mine");
  const Artifact more = stage_artifact(store, "more", {{"a.png", "A2"}, {"b.png", "B"}}, "labels");
  const int64_t writes = files.writes();
  try {
    publish_outputs("/out", {{"labels", more}}, files);
    FAIL("a folder is in the way");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("/out/labels/b.png") && Catch::Contains("a folder is where"));
  }
  CHECK(files.writes() == writes);
  CHECK(files.read("/out/labels/a.png") == "A");
}

TEST_CASE("publish: changes a killed run committed are made by the next, before its own") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const Artifact labels = stage_artifact(store, "labels", {{"a.png", "A"}, {"b.png", "B"}});
  publish_outputs("/out", {{"labels", labels}}, files);
  const std::string manifest = files.read("/out/manifest.json");
  // What a run killed after its commit leaves: a.png still to move, b.png to go, its manifest.
  files.write("/out/.olt-publish/files/labels/a.png", "A2");
  files.write("/out/.olt-publish/manifest.json", "theirs");
  files.write("/out/.olt-publish/journal.json",
              json{{"put", {"labels/a.png", "labels/moved-already.png"}},
                   {"gone", {{{"path", "labels/b.png"}, {"sha256", sha256_hex("B")}}}}}
                  .dump());
  finish_publishing("/out", files);
  CHECK(files.read("/out/labels/a.png") == "A2");
  CHECK_FALSE(files.stat("/out/labels/b.png").exists());
  CHECK(files.read("/out/manifest.json") == "theirs");
  CHECK_FALSE(files.stat("/out/.olt-publish").exists());

  // This run's publish then brings the output to its own files.
  publish_outputs("/out", {{"labels", labels}}, files);
  CHECK(files.read("/out/labels/a.png") == "A");
  CHECK(files.read("/out/labels/b.png") == "B");
  CHECK(files.read("/out/manifest.json") == manifest);

  // A journal that is not one is an error naming it, not a crash, and nothing it lists is made.
  files.write("/out/.olt-publish/files/labels/a.png", "A3");
  for (const std::string damaged :
       {"{\"put\": 3}", "{\"put\": [\"labels/a.png\"]}", "{\"gone\": []}",
        "{\"put\": [\"labels/a.png\", 4], \"gone\": []}", "{\"put\": [\"labels/a.png\"], \"gone\": [\"labels/b.png\"]}",
        "{\"put\": [\"labels/a.png\"], \"gone\": [{\"path\": \"labels/b.png\"}]}", "[\"labels/a.png\"]",
        "{\"put\": [[\"labels/a.png\"]], \"gone\": []}", "{\"put\": {\"x\": \"labels/a.png\"}, \"gone\": []}",
        "{\"put\": [\"labels/a.png\"], \"gone\": [[]]}", "{\"put\": [\"labels/a.png\"], \"gone\": [", ""}) {
    CAPTURE(damaged);
    files.write("/out/.olt-publish/journal.json", damaged);
    try {
      publish_outputs("/out", {{"labels", labels}}, files);
      FAIL("the journal is damaged");
    } catch (const InputError& e) {
      CHECK_THAT(e.what(),
                 Catch::Contains("/out/.olt-publish/journal.json") && Catch::Contains("remove /out/.olt-publish"));
    }
    CHECK(files.read("/out/labels/a.png") == "A");
  }
}

TEST_CASE("publish: a journal of many paths, written in pieces, is read back whole") {
  // 100,000 paths: the journal's text passes a piece's size (1 MB) several times.
  std::vector<std::string> put;
  for (int i = 0; i < 100000; ++i) put.push_back("labels/rgbd/class/" + std::to_string(i) + ".png");
  const Listed gone = {{"labels/old.png", sha256_hex("old")}, {"labels/\u00e9t\u00e9 \"q\".png", sha256_hex("x")}};
  std::string text;
  size_t pieces = 0;
  journal_pieces(
      put.size(), [&](size_t i) { return put[i]; }, gone,
      [&](std::string_view piece) {
        text += piece;
        ++pieces;
      });
  CHECK(pieces > 2);
  // Every path, in order, and the files to remove.
  CHECK(json::parse(text) == json{{"put", put},
                                  {"gone", json::array({{{"path", gone[0].first}, {"sha256", gone[0].second}},
                                                        {{"path", gone[1].first}, {"sha256", gone[1].second}}})}});
}

TEST_CASE("publish: the listing kept in the cache stands for the manifest it copies, and only for it") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const fs::path listing = "/cache/outputs/out.listing";
  const Artifact first = stage_artifact(store, "first", {{"a.png", "A"}, {"b.png", "B"}}, "labels");
  publish_outputs("/out", {{"labels", first}}, files, listing);
  const std::string digest = sha256_hex(files.read("/out/manifest.json"));
  CHECK(files.read(listing) == "# olt listing 1\n" + digest + "\n" + sha256_hex("A") + " 12 labels/a.png\n" +
                                   sha256_hex("B") + " 12 labels/b.png\n");

  // A listing of this manifest is what the last publish wrote: here it says a.png held other bytes,
  // so a.png is published again (a new file) with b.png's change.
  const uint64_t a = files.stat("/out/labels/a.png").identity;
  files.write(listing, "# olt listing 1\n" + digest + "\n" + sha256_hex("other") + " 12 labels/a.png\n" +
                           sha256_hex("B") + " 12 labels/b.png\n");
  const Artifact second = stage_artifact(store, "second", {{"a.png", "A"}, {"b.png", "B2"}}, "labels");
  publish_outputs("/out", {{"labels", second}}, files, listing);
  CHECK(files.stat("/out/labels/a.png").identity != a);
  CHECK(files.read("/out/labels/b.png") == "B2");

  // A listing of another manifest, of another format, or a damaged one, is not used: the manifest is read.
  int edits = 0;
  for (const std::string& stale : {"# olt listing 1\n0000\n" + sha256_hex("other") + " 12 labels/a.png\n",
                                   "# olt listing 2\n" + sha256_hex(files.read("/out/manifest.json")) + "\n" +
                                       sha256_hex("other") + " 12 labels/a.png\n",
                                   "# olt listing 1\n" + sha256_hex(files.read("/out/manifest.json")) + "\n" +
                                       sha256_hex("other") + " 99 labels/a.png\n"}) {
    const uint64_t kept = files.stat("/out/labels/a.png").identity;
    files.write(listing, stale);
    const std::string edit = std::to_string(++edits);  // b.png changes every time
    const Artifact next = stage_artifact(store, "next" + edit, {{"a.png", "A"}, {"b.png", "B" + edit}}, "labels");
    publish_outputs("/out", {{"labels", next}}, files, listing);
    CHECK(files.stat("/out/labels/a.png").identity == kept);
    CHECK(files.read(listing).rfind("# olt listing 1\n" + sha256_hex(files.read("/out/manifest.json")) + "\n", 0) ==
          0);  // written anew
  }
}

TEST_CASE("publish: the manifest is nlohmann's indented JSON, with sensors and observations - an empty one too") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const fs::path dir = store.begin("frames");
  ArtifactFolder out(dir, store.files());
  out.write("a.png", "A");
  out.write("b.png", "B");
  out.publish(Published{"a.png", "labels/cam \"1\"/a.png", "class_label", "cam \"1\" \xc3\xa9\t\\", "1305031102.175304",
                        1305031102.175304});
  out.publish(Published{"b.png", "labels/b.png", "instance_label", "", "", 0});
  // Another file of a.png's observation, and one of its id at another time.
  out.write("c.png", "C");
  out.write("d.png", "D");
  out.publish(Published{"c.png", "labels/cam \"1\"/c.png", "instance_label", "cam \"1\" \xc3\xa9\t\\",
                        "1305031102.175304", 1305031102.175304});
  out.publish(Published{"d.png", "labels/d.png", "class_label", "cam", "1305031102.175304", 0.5});
  std::string list;
  out.publish_list([&](std::string_view piece) { list += piece; });
  out.write("publish.json", list);
  const Artifact artifact = store.commit("frames", dir);
  publish_outputs("/out", {{"labels", artifact}}, files);
  const std::string text = files.read("/out/manifest.json");
  const json manifest = json::parse(text);
  CHECK(text == manifest.dump(1) + "\n");
  REQUIRE(manifest["files"].size() == 4);
  CHECK(manifest["files"][1]["sensor"] == "cam \"1\" \xc3\xa9\t\\");
  CHECK(manifest["files"][1]["observation"]["timestamp"] == 1305031102.175304);
  CHECK(manifest["files"][2]["observation"]["timestamp"] == 1305031102.175304);
  CHECK(manifest["files"][3]["observation"]["timestamp"] == 0.5);
  CHECK_FALSE(manifest["files"][0].contains("observation"));

  const fs::path empty_dir = store.begin("nothing");
  ArtifactFolder nothing(empty_dir, store.files());
  nothing.write("publish.json", "[]");
  publish_outputs("/out", {{"labels", store.commit("nothing", empty_dir)}}, files);
  CHECK(files.read("/out/manifest.json") == "{\n \"files\": []\n}\n");
  CHECK_FALSE(files.stat("/out/labels/b.png").exists());
}

TEST_CASE("publish: a manifest of several megabytes is written and listed in pieces, the bytes dump(1) writes") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  std::map<std::string, std::string> many;
  // Their paths, ~100 bytes each, fill more than the megabyte block the entries keep paths in.
  const auto name = [](int i) {
    return "frame_" + std::to_string(100000 + i) +
           "_class_labels_at_colour_of_a_camera_named_at_great_length_by_its_maker.png";
  };
  for (int i = 0; i < 12000; ++i) many[name(i)] = "x";
  const std::vector<std::pair<std::string, Artifact>> artifacts = {{"labels", stage_artifact(store, "labels", many)}};
  const fs::path listing = output_listing("/cache", "/out");
  publish_outputs("/out", artifacts, files, listing);
  const std::string text = files.read("/out/manifest.json");
  REQUIRE(text.size() > 2 * (1 << 20));  // pieces of a megabyte: three of them
  const json manifest = json::parse(text);
  CHECK(text == manifest.dump(1) + "\n");
  CHECK(manifest["files"].size() == 12000);
  REQUIRE(12000 * ("labels/" + name(0)).size() > (1 << 20));
  CHECK(manifest["files"][11999]["path"] == "labels/" + name(11999));  // in the entries' second block
  CHECK(manifest["files"][0]["path"] == "labels/" + name(0));
  // The listing names the manifest's digest and every file: read by the next publish, it finds
  // one changed file among the 12,000 and writes that one.
  CHECK(files.read(listing).rfind("# olt listing 1\n" + sha256_hex(text) + "\n", 0) == 0);
  many["frame_100007_class_labels_at_colour.png"] = "y";
  const Artifact edited = stage_artifact(store, "labels_v2", many, "labels");
  const int64_t writes = files.writes();
  publish_outputs("/out", {{"labels", edited}}, files, listing);
  CHECK(files.read("/out/labels/frame_100007_class_labels_at_colour.png") == "y");
  CHECK(files.writes() - writes < 20);  // the file, the manifest's pieces, the journal, the listing's
}

TEST_CASE("entries: a path STAGE/FILE is the stage's folder and the file's name, compared and written as the whole") {
  // Compared as the whole text, bytewise, wherever the parts meet.
  CHECK(EntryPath{"ab/", "c"}.compare({"", "ab/c"}) == 0);
  CHECK(EntryPath{"ab/", "c"} == EntryPath{"a", "b/c"});
  CHECK(EntryPath{"a/", "b"} < EntryPath{"", "a/c"});
  CHECK(EntryPath{"", "a/b"} < EntryPath{"a/", "bc"});    // a prefix first
  CHECK(EntryPath{"", "z"} < EntryPath{"", "\xc3\xa9"});  // as unsigned bytes, as std::string sorts
  CHECK_FALSE(EntryPath{"a/", "b"} < EntryPath{"a/", "b"});
  std::string scratch;
  CHECK(EntryPath{"labels/", "x.png"}.in(scratch) == "labels/x.png");

  Artifact artifact;
  artifact.files = {{"cam/a.png", Digest(sha256_hex("a")), 1, "", ""},
                    {"cam/b.png", Digest(sha256_hex("b")), 1, "", ""}};
  artifact.files.sort();
  Entries entries;
  entries.add_stage("labels", artifact);
  entries.add(Published{"cam/a.png", "labels/cam/a.png", "class_label", "cam", "1", 0.5}, 0);
  entries.add(Published{"cam/b.png", "elsewhere/b.png", "class_label", "cam", "2", 1.5}, 1);
  CHECK(entries.path(entries.list[0]).head == "labels/");  // not held again
  CHECK(entries.path(entries.list[0]).str() == "labels/cam/a.png");
  CHECK(entries.path(entries.list[1]).head.empty());
  CHECK(entries.path(entries.list[1]).str() == "elsewhere/b.png");
  std::string manifest;
  manifest_pieces(entries, [&](std::string_view piece) { manifest += piece; });
  CHECK_THAT(manifest, Catch::Contains("\"path\": \"labels/cam/a.png\""));
  CHECK_THAT(manifest, Catch::Contains("\"path\": \"elsewhere/b.png\""));
}

TEST_CASE("entries: put in a sorting order in place - any permutation, and only a permutation") {
  Artifact artifact;
  for (const char* name : {"a", "b", "c", "d", "e", "f"}) artifact.files.add(name, Digest(sha256_hex(name)), 1);
  artifact.files.sort();
  // Entries added in the order of `names` (two stages: "second" repeats some paths of "first").
  const auto entries_of = [&](const std::vector<std::pair<int, std::string>>& names) {
    auto entries = std::make_unique<Entries>();
    int stage = -1;
    for (const auto& [in_stage, name] : names) {
      if (in_stage != stage) entries->add_stage(in_stage == 0 ? "first" : "second", artifact), stage = in_stage;
      entries->add(Published{name, "out/" + name, "test", "", "", 0}, *artifact.files.place(name));
    }
    return entries;
  };
  const auto listed = [](const Entries& entries) {
    std::vector<std::string> out;
    for (const Entry& e : entries.list) out.push_back(entries.path(e).str() + " " + entries.stage(e));
    return out;
  };
  const std::vector<std::string> expected = {"out/a first",  "out/b first", "out/c first", "out/c second",
                                             "out/d second", "out/e first", "out/f second"};
  for (const auto& names : std::vector<std::vector<std::pair<int, std::string>>>{
           {{0, "a"}, {0, "b"}, {0, "c"}, {0, "e"}, {1, "c"}, {1, "d"}, {1, "f"}},     // sorted but for one
           {{0, "e"}, {0, "c"}, {0, "b"}, {0, "a"}, {1, "f"}, {1, "d"}, {1, "c"}},     // reversed in each stage
           {{0, "b"}, {0, "e"}, {0, "a"}, {0, "c"}, {1, "f"}, {1, "c"}, {1, "d"}}}) {  // cycles of 2 and 4
    auto entries = entries_of(names);
    const std::vector<uint32_t> order = sorting_order(*entries);
    CHECK(sorted(*entries) == (listed(*entries) == expected));  // sorted() says what the list is
    put_in_order(*entries, order);
    CHECK(listed(*entries) == expected);
    CHECK(sorted(*entries));
    put_in_order(*entries, {0, 1, 2, 3, 4, 5, 6});  // the identity leaves them
    CHECK(listed(*entries) == expected);
  }
  auto one = entries_of({{0, "a"}});
  put_in_order(*one, {0});
  CHECK(listed(*one) == std::vector<std::string>{"out/a first"});
  Entries none;
  put_in_order(none, {});
  CHECK(sorted(none));
  // Not a permutation: refused before any entry moves.
  auto entries = entries_of({{0, "b"}, {0, "a"}, {0, "c"}});
  const auto before = listed(*entries);
  CHECK_THROWS_AS(put_in_order(*entries, {1, 1, 0}), std::invalid_argument);
  CHECK_THROWS_AS(put_in_order(*entries, {1, 0, 3}), std::invalid_argument);
  CHECK_THROWS_AS(put_in_order(*entries, {1, 0}), std::invalid_argument);
  CHECK(listed(*entries) == before);
  CHECK_FALSE(sorted(*entries));
}

TEST_CASE(
    "manifest text: held where it is at most held_bytes, else made again - the same digest and bytes either way") {
  // Long paths: a manifest of several pieces (a megabyte each), so a text can be let go midway.
  Artifact artifact;
  for (int i = 0; i < 8000; ++i)
    artifact.files.add(
        "cam/class/" + std::to_string(100000 + i) + "_at_colour_of_a_camera_named_at_length_by_its_maker.png",
        Digest(sha256_hex(std::to_string(i))), 1);
  artifact.files.sort();
  Entries entries;
  entries.add_stage("labels", artifact);
  for (size_t i = 0; i < artifact.files.size(); ++i) {
    const std::string file(artifact.files[i].path);
    entries.add(Published{file, "labels/" + file, "class_label", "cam", std::to_string(i), 0.5 * i}, i);
  }
  std::string made;
  manifest_pieces(entries, [&](std::string_view piece) { made += piece; });
  REQUIRE(made.size() > 2 * (1 << 20));  // three pieces
  const ManifestText held = manifest_text(entries, made.size()), not_held = manifest_text(entries, made.size() - 1),
                     let_go = manifest_text(entries, made.size() / 2);  // after its first pieces
  CHECK(held.digest == sha256_hex(made));
  CHECK(not_held.digest == held.digest);
  CHECK(let_go.digest == held.digest);
  REQUIRE(held.text);
  CHECK(*held.text == made);
  CHECK_FALSE(not_held.text);
  CHECK_FALSE(let_go.text);
  for (const ManifestText* m : {&held, &not_held, &let_go}) {
    std::string written;
    m->pieces(entries, [&](std::string_view piece) { written += piece; });
    CHECK(written == made);
  }
}

TEST_CASE("publish: a mount point inside the output gets its files by copies renamed into place, synced") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  files.make_folders("/out/labels");
  files.mount("/out/labels");  // another file system: the staging folder's renames cannot reach it
  publish_outputs("/out",
                  {{"labels", stage_artifact(store, "labels", {{"a.png", "A"}, {"b.png", "B"}})},
                   {"poses", stage_artifact(store, "poses", {{"trajectory.txt", "T"}})}},
                  files);
  CHECK(files.read("/out/labels/a.png") == "A");
  CHECK(files.read("/out/labels/b.png") == "B");
  CHECK(files.read("/out/poses/trajectory.txt") == "T");
  CHECK(files.list("/out") == std::vector<std::string>{"labels", "manifest.json", "poses"});  // nothing staged left
  CHECK(files.list("/out/labels") == std::vector<std::string>{"a.png", "b.png"});  // no copy left beside them
  // An edit: the changed file replaced the same way, the other left as it was.
  const Artifact edited = stage_artifact(store, "labels_v2", {{"a.png", "A"}, {"b.png", "B2"}}, "labels");
  const int64_t syncs = files.syncs();
  const uint64_t a = files.stat("/out/labels/a.png").identity;
  publish_outputs("/out", {{"labels", edited}}, files);
  CHECK(files.read("/out/labels/b.png") == "B2");
  CHECK(files.stat("/out/labels/a.png").identity == a);
  CHECK(!files.stat("/out/poses").exists());
  CHECK(files.syncs() - syncs == 3);  // the staging, the mount's folder (its own file system), the output
}

TEST_CASE("publish: a killed publish's journal of 100,000 paths is finished by the next run, path by path") {
  MemoryFileSystem files;
  // The staged files of every 997th path; the others were moved already (a run killed midway).
  std::vector<std::string> put;
  for (int i = 0; i < 100000; ++i) put.push_back("labels/rgbd/class/" + std::to_string(i) + ".png");
  for (size_t i = 0; i < put.size(); i += 997) files.write("/out/.olt-publish/files/" + put[i], "P" + put[i]);
  files.write("/out/gone.png", "G");
  write_pieces(files, "/out/.olt-publish/journal.json", [&](const PieceSink& sink) {
    journal_pieces(
        put.size(), [&](size_t i) { return put[i]; }, {{"gone.png", sha256_hex("G")}}, sink);
  });
  finish_publishing("/out", files);
  for (size_t i = 0; i < put.size(); ++i) {
    if (i % 997 == 0) {
      INFO(put[i]);
      CHECK(files.read("/out/" + put[i]) == "P" + put[i]);
    }
  }
  CHECK_FALSE(files.stat("/out/labels/rgbd/class/1.png").exists());  // not staged: nothing made
  CHECK_FALSE(files.stat("/out/gone.png").exists());
  CHECK_FALSE(files.stat("/out/.olt-publish").exists());
}

TEST_CASE("publish: a process that keeps memory knows the manifest it published - and sees one edited since") {
  // Counts how often the output's manifest is hashed.
  struct CountingFileSystem : MemoryFileSystem {
    mutable int manifest_hashed = 0;
    std::string sha256(const fs::path& file) const override {
      manifest_hashed += file.filename() == "manifest.json";
      return MemoryFileSystem::sha256(file);
    }
  } files;
  const Store store("/cache", files);
  const Artifact first = stage_artifact(store, "first", {{"a.png", "A"}, {"b.png", "B"}}, "labels");
  publish_outputs("/out", {{"labels", first}}, files);
  const std::string manifest = files.read("/out/manifest.json");
  const uint64_t published = files.stat("/out/manifest.json").identity;

  // Without memory kept (`olt run`) the manifest there is hashed every publish.
  files.manifest_hashed = 0;
  publish_outputs("/out", {{"labels", first}}, files);
  CHECK(files.manifest_hashed == 1);

  olt::test::KeepingMemory keeping(64 << 20);           // as `olt watch`
  publish_outputs("/out", {{"labels", first}}, files);  // hashed once more, then remembered
  files.manifest_hashed = 0;
  publish_outputs("/out", {{"labels", first}}, files);  // nothing changed: nothing written, nothing hashed
  CHECK(files.manifest_hashed == 0);
  CHECK(files.stat("/out/manifest.json").identity == published);

  // Edited by hand in place, to as many other bytes: published again, though the file is the same one.
  std::string edited = manifest;
  edited[edited.find("a.png")] = 'x';
  files.write("/out/manifest.json", edited);
  REQUIRE(files.stat("/out/manifest.json").identity == published);
  publish_outputs("/out", {{"labels", first}}, files);
  CHECK(files.manifest_hashed == 1);
  CHECK(files.read("/out/manifest.json") == manifest);

  // A publish that changed the output remembers the manifest it wrote.
  const Artifact second = stage_artifact(store, "second", {{"a.png", "A2"}, {"b.png", "B"}}, "labels");
  publish_outputs("/out", {{"labels", second}}, files);
  files.manifest_hashed = 0;
  publish_outputs("/out", {{"labels", second}}, files);
  CHECK(files.manifest_hashed == 0);
}

TEST_CASE("publish: a process that keeps memory lists its files in the order a plain one does, edit after edit") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  // Two stages whose paths interleave (data/0, data/1, ... from either), the second's bytes
  // changed by `version`, its list longer with `more` (another publish list: sorted afresh).
  const auto artifacts = [&](int version, bool more) {
    std::map<std::string, std::string> odd, even;
    for (int i = 0; i < 40; ++i) (i % 2 ? odd : even)[std::to_string((i * 7) % 40)] = std::to_string(i);
    for (auto& [name, bytes] : even) bytes += "v" + std::to_string(version);
    if (more) even["19b"] = "more";
    const std::string key = "even" + std::to_string(version) + (more ? "+" : "");
    return std::vector<std::pair<std::string, Artifact>>{{"odd", stage_artifact(store, "odd", odd, "data")},
                                                         {"even", stage_artifact(store, key, even, "data")}};
  };
  const auto listed = [&](const std::string& output) {
    std::vector<std::pair<std::string, std::string>> out;                      // path, stage
    const json manifest = json::parse(files.read(output + "/manifest.json"));  // held: the loop reads into it
    for (const auto& f : manifest["files"]) out.emplace_back(f["path"], f["stage"]);
    return out;
  };
  const std::vector<std::pair<int, bool>> edits = {{1, false}, {2, false}, {3, true}, {4, true}};
  std::vector<std::vector<std::pair<std::string, std::string>>> plain;  // as `olt run` lists them
  for (const auto& [version, more] : edits) {
    publish_outputs("/plain", artifacts(version, more), files);
    plain.push_back(listed("/plain"));
    CHECK(plain.back().size() == (more ? 41u : 40u));
    CHECK(std::is_sorted(plain.back().begin(), plain.back().end()));
  }
  olt::test::KeepingMemory keeping(64 << 20);  // as `olt watch`: the order found at one edit kept for the next
  for (size_t k = 0; k < edits.size(); ++k) {
    INFO("version " << edits[k].first);
    publish_outputs("/kept", artifacts(edits[k].first, edits[k].second), files);
    CHECK(listed("/kept") == plain[k]);
  }
}

TEST_CASE("publish: a process that keeps memory does not look at files its manifest lists in an output as it left it") {
  // Counts how often a published file is looked at in the output.
  struct CountingFileSystem : MemoryFileSystem {
    mutable std::atomic<int> looked{0};
    FileStat stat(const fs::path& path, bool follow_link) const override {
      looked += path.string().rfind("/out/labels/", 0) == 0 && path.extension() == ".png";
      return MemoryFileSystem::stat(path, follow_link);
    }
  } files;
  const Store store("/cache", files);
  const auto labels = [&](const std::string& key, const std::string& a) {
    return stage_artifact(store, key, {{"a.png", a}, {"b.png", "B"}, {"c.png", "C"}}, "labels");
  };
  const auto publish = [&](const std::string& key, const std::string& a) {
    const Artifact artifact = labels(key, a);
    files.looked = 0;
    publish_outputs("/out", {{"labels", artifact}}, files);
    return files.looked.load();
  };
  CHECK(publish("1", "A") == 3);   // none there: each looked at
  CHECK(publish("2", "AA") == 3);  // `olt run`: each looked at again

  olt::test::KeepingMemory keeping(64 << 20);  // as `olt watch`
  CHECK(publish("3", "AAA") == 3);             // what the output holds is not known yet
  CHECK(publish("4", "AAAA") == 0);
  CHECK(publish("4", "AAAA") == 0);  // nothing changed
  CHECK(files.read("/out/labels/a.png") == "AAAA");
  CHECK(files.read("/out/labels/b.png") == "B");

  // Changed by hand since: each file looked at, and put right.
  files.remove("/out/labels/b.png");
  files.write("/out/labels/c.png", "CCCC");
  CHECK(publish("5", "AAAAA") == 3);
  CHECK(files.read("/out/labels/b.png") == "B");
  CHECK(files.read("/out/labels/c.png") == "C");
  CHECK(files.read("/out/labels/a.png") == "AAAAA");
  CHECK(publish("6", "AAAAAA") == 0);
  files.write("/out/labels/new.txt", "");  // anything made in a folder published into
  CHECK(publish("7", "AAAAAAA") == 3);
  files.remove("/out/manifest.json");
  CHECK(publish("7", "AAAAAAA") == 3);
  CHECK(files.read("/out/manifest.json").find("labels/c.png") != std::string::npos);
}

TEST_CASE("publish: an output as it was left is seen changed when a folder on the way moves - or cannot be watched") {
  // Counts how often a published file is looked at in the output; `watched` false: a file system
  // that cannot watch folders (a network one).
  struct CountingFileSystem : MemoryFileSystem {
    bool watched = true;
    mutable std::atomic<int> looked{0};
    FileStat stat(const fs::path& path, bool follow_link) const override {
      looked += path.string().rfind("/out/deep/", 0) == 0 && path.extension() == ".png";
      return MemoryFileSystem::stat(path, follow_link);
    }
    std::unique_ptr<FolderWatch> watch(const std::vector<fs::path>& folders) override {
      return watched ? MemoryFileSystem::watch(folders) : nullptr;
    }
  };
  olt::test::KeepingMemory keeping(64 << 20);  // as `olt watch`; each case starts afresh below
  for (const bool watched : {true, false}) {
    INFO((watched ? "watched" : "not watched"));
    olt::keep_in_memory(0);  // each a process of its own (the file systems may share an address)
    olt::keep_in_memory(64 << 20);
    CountingFileSystem files;
    files.watched = watched;
    const Store store("/cache", files);
    const auto publish = [&](const std::string& key, const std::string& x) {
      const Artifact artifact = stage_artifact(store, key, {{"x.png", x}, {"y.png", "Y"}}, "deep/a/b");
      files.looked = 0;
      publish_outputs("/out", {{"deep", artifact}}, files);
      return files.looked.load();
    };
    CHECK(publish("1", "X") == 2);
    CHECK(publish("2", "XX") == (watched ? 0 : 2));
    // A folder the output publishes through, not into, moved away: every file looked at, put back.
    files.rename("/out/deep/a", "/moved");
    CHECK(publish("3", "XXX") == 2);
    CHECK(files.read("/out/deep/a/b/y.png") == "Y");
    CHECK(files.read("/out/deep/a/b/x.png") == "XXX");
    CHECK(publish("4", "XXXX") == (watched ? 0 : 2));
  }
}

TEST_CASE("publish: an output as a process left it is seen changed by hand on the real file system too") {
  TempDir temp;
  FileSystem& files = real_file_system();
  const Store store(temp.path() / "cache", files);
  const fs::path out = temp.path() / "p/out";
  const auto publish = [&](const std::string& key, const std::string& a) {
    publish_outputs(out, {{"labels", stage_artifact(store, key, {{"a.png", a}, {"b.png", "B"}}, "labels")}}, files);
  };
  olt::test::KeepingMemory keeping(64 << 20);
  publish("1", "A");
  publish("2", "AA");
  files.remove(out / "labels/b.png");
  publish("3", "AAA");
  CHECK(files.read(out / "labels/b.png") == "B");
  files.write(out / "labels/b.png", "BBB");  // in place
  publish("4", "AAAA");
  CHECK(files.read(out / "labels/b.png") == "B");
  fs::rename(out / "labels", temp.path() / "moved");
  publish("5", "AAAAA");
  CHECK(files.read(out / "labels/b.png") == "B");
  CHECK(files.read(out / "labels/a.png") == "AAAAA");
  // The output's parent put in another's place (moved away, a copy where it was): nothing the watch
  // watches was moved, but it follows folders, not paths; the next publish watches the copy, and a
  // hand change there is seen.
  fs::rename(temp.path() / "p", temp.path() / "p.old");
  fs::copy(temp.path() / "p.old", temp.path() / "p", fs::copy_options::recursive);
  publish("6", "A6");
  files.remove(out / "labels/b.png");
  publish("7", "A7");
  CHECK(files.read(out / "labels/b.png") == "B");
  files.write(temp.path() / "p.old/out/labels/b.png", "old");  // where the output was: not its business
  files.remove(out / "labels/b.png");
  publish("8", "A8");
  CHECK(files.read(out / "labels/b.png") == "B");
}

TEST_CASE("publish: an artifact passed without its file list is listed when it publishes something, not otherwise") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  Artifact source = stage_artifact(store, "source", {});  // publishes nothing
  Artifact labels = stage_artifact(store, "labels", {{"a.png", "A"}});
  const ArtifactFiles labels_files = labels.files;
  source.files = ArtifactFiles();
  labels.files = ArtifactFiles();
  std::vector<std::string> listed;
  publish_outputs("/out", {{"source", source}, {"labels", labels}}, files, {},
                  [&](const std::string& stage, const Artifact& artifact) {
                    listed.push_back(stage);
                    CHECK(artifact.key == "labels");
                    return labels_files;
                  });
  CHECK(listed == std::vector<std::string>{"labels"});  // once, and not the source's
  CHECK(files.read("/out/labels/a.png") == "A");
  CHECK(json::parse(files.read("/out/manifest.json"))["files"].size() == 1);
}

TEST_CASE("publish: a process that keeps memory writes the files its run wrote from their bytes - clones stay clones") {
  // Counts the cache files copied into the output (read back and hashed).
  struct CountingFileSystem : MemoryFileSystem {
    std::atomic<int> copied{0};
    Copied copy_hashed(const fs::path& from, const fs::path& to) override {
      ++copied;
      return MemoryFileSystem::copy_hashed(from, to);
    }
  };
  const std::map<std::string, std::string> written = {{"a.png", "A"}, {"b.png", "BB"}, {"c.png", "CCC"}};
  const auto made = [&](CountingFileSystem& files) {  // the run's stage: its files written
    return stage_artifact(Store("/cache", files), "labels", written, "labels");
  };
  const auto publish = [&](CountingFileSystem& files, const Artifact& labels, const std::string& out) {
    files.copied = 0;
    publish_outputs(out, {{"labels", labels}}, files);
    for (const auto& [name, bytes] : written) CHECK(files.read(out + "/labels/" + name) == bytes);
    return files.copied.load();
  };
  forget_run_memory();
  CountingFileSystem plain;
  CHECK(publish(plain, made(plain), "/out") == 3);  // `olt run`: each copied from the cache, verified

  olt::test::KeepingMemory keeping;  // `olt watch`: the first file tells whether copies are clones
  CountingFileSystem kept;
  const Artifact labels = made(kept);
  CHECK(publish(kept, labels, "/out") == 1);
  CHECK(kept.read("/out/manifest.json") == plain.read("/out/manifest.json"));
  forget_run_memory();  // a run's bytes are let go at its end: the next run copies what it did not write
  CHECK(publish(kept, labels, "/again") == 3);

  CountingFileSystem cloning;  // XFS, Btrfs: a clone shares the cache's blocks, where a write would not
  cloning.clone_copies();
  CHECK(publish(cloning, made(cloning), "/out") == 3);
  forget_run_memory();
}

TEST_CASE(
    "publish: changes staged by this process are moved without a look at each - a file gone fails, the next run "
    "finishes") {
  // Counts the looks at staged files.
  struct CountingFileSystem : MemoryFileSystem {
    mutable std::atomic<int> looked{0};
    FileStat stat(const fs::path& path, bool follow_link = false) const override {
      looked += path.string().rfind("/out/.olt-publish/files/", 0) == 0;
      return MemoryFileSystem::stat(path, follow_link);
    }
  } files;
  // What a publish stages: three files to move (one in a folder of its own) and the manifest; then
  // one of them taken away before it is moved.
  const std::map<std::string, std::string> staged = {
      {"labels/a.png", "A"}, {"labels/b.png", "B"}, {"labels/c/d.png", "D"}};
  for (const auto& [path, bytes] : staged) files.write("/out/.olt-publish/files/" + path, bytes);
  files.write("/out/.olt-publish/manifest.json", "manifest");
  files.write("/out/.olt-publish/journal.json",
              json{{"put", {"labels/a.png", "labels/b.png", "labels/c/d.png"}}, {"gone", json::array()}}.dump());
  files.remove("/out/.olt-publish/files/labels/b.png");
  CHECK_THROWS_AS(apply_pending(files, "/out", Pending::staged_now), FileSystemError);
  CHECK(files.looked == 0);
  CHECK(files.read("/out/labels/a.png") == "A");  // the others moved all the same
  CHECK(files.read("/out/labels/c/d.png") == "D");
  CHECK(files.stat("/out/.olt-publish/journal.json").is_file());  // the publish is not finished
  CHECK_FALSE(files.stat("/out/manifest.json").exists());
  files.write("/out/.olt-publish/files/labels/b.png", "B");  // back: the next run moves it
  apply_pending(files, "/out");                              // the next run's: each file looked for, those there moved
  CHECK(files.looked == 3);
  CHECK(files.read("/out/labels/b.png") == "B");
  CHECK(files.read("/out/manifest.json") == "manifest");
  CHECK_FALSE(files.stat("/out/.olt-publish").exists());
}

TEST_CASE("publish: a symbolic link on the way of any staged file stops the publish before any file moves") {
  MemoryFileSystem files;
  files.make_folders("/elsewhere");
  files.make_folders("/out");
  files.symlink("/elsewhere", "/out/other");
  for (const std::string path : {"labels/a.png", "other/b.png"}) files.write("/out/.olt-publish/files/" + path, path);
  files.write("/out/.olt-publish/journal.json",
              json{{"put", {"labels/a.png", "other/b.png"}}, {"gone", json::array()}}.dump());
  CHECK_THROWS_WITH(apply_pending(files, "/out", Pending::staged_now), Catch::Contains("/out/other/b.png"));
  CHECK_FALSE(files.stat("/out/labels/a.png").exists());
  CHECK_FALSE(files.stat("/out/labels").exists());
  CHECK(files.files_below("/elsewhere").empty());
}

TEST_CASE("publish: bytes written in pieces are kept whole for publishing - a file too large to keep is copied") {
  olt::test::KeepingMemory keeping;
  forget_run_memory();
  struct CountingFileSystem : MemoryFileSystem {  // counts the files copied from the cache
    std::atomic<int> copied{0};
    Copied copy_hashed(const fs::path& from, const fs::path& to) override {
      ++copied;
      return MemoryFileSystem::copy_hashed(from, to);
    }
  } files;
  const Store store("/cache", files);
  const fs::path dir = store.begin("export");
  ArtifactFolder out(dir, files);
  const std::string small = "a piece, " + std::string(1000, 's') + ", another";
  const std::string large((size_t{4} << 20) + 1, 'L');  // more than a file kept may hold
  // a.json is the first published (it tells whether copies clone), then large.json, small.json.
  out.write("a.json", "first");
  out.publish("a.json", "export/a.json", "test");
  for (const auto& [name, bytes] : {std::pair{"small.json", small}, std::pair{"large.json", large}}) {
    out.write_pieces(name, [&, &bytes = bytes](const PieceSink& sink) {
      for (size_t at = 0; at < bytes.size(); at += 1000) sink(std::string_view(bytes).substr(at, 1000));
    });
    out.publish(name, std::string("export/") + name, "test");
  }
  REQUIRE(kept_for_run<std::string>(sha256_hex(small)) != nullptr);
  CHECK(*kept_for_run<std::string>(sha256_hex(small)) == small);
  CHECK(kept_for_run<std::string>(sha256_hex(large)) == nullptr);
  std::string list;
  out.publish_list([&](std::string_view piece) { list += piece; });
  out.write("publish.json", list);
  publish_outputs("/out", {{"export", store.commit("export", dir, out.take_described())}}, files);
  CHECK(files.read("/out/export/small.json") == small);
  CHECK(files.read("/out/export/large.json") == large);
  CHECK(files.copied == 2);  // the first and the large one: small.json written from memory
  forget_run_memory();
}

TEST_CASE(
    "publish: in a process that keeps memory, a file written this run is published as written - a damaged copy is "
    "refused the next run") {
  olt::test::KeepingMemory keeping;
  forget_run_memory();
  MemoryFileSystem files;
  const Store store("/cache", files);
  // a.png is the first published (it tells whether copies clone); b.png's cache file is then damaged.
  const Artifact labels = stage_artifact(store, "labels", {{"a.png", "AAAA"}, {"b.png", "BBBB"}});
  files.write(labels.dir / "b.png", "BBBX");
  publish_outputs("/out", {{"labels", labels}}, files);
  CHECK(files.read("/out/labels/b.png") == "BBBB");  // the bytes written, which the manifest lists
  forget_run_memory();                               // the next run: b.png is not its own
  try {
    publish_outputs("/again", {{"labels", labels}}, files);
    FAIL("the entry is damaged");
  } catch (const DamagedArtifact& e) {
    CHECK_THAT(e.what(), Catch::Contains("/b.png") && Catch::Contains("does not hold the bytes recorded"));
  }
}
