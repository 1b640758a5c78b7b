// The runtime's unit engine on a stage with made-up units, on a file system in memory: each unit keyed
// by its record, run once and then found, shared across shards, missing ones named for a merge, and
// the reasons a plan gives (the same record comparison as for stages).
#include "runtime/unit_engine.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <mutex>

#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "runtime/artifact_folder.h"
#include "runtime/execute.h"
#include "runtime/explain.h"
#include "support/keeping_memory.h"
#include "support/memory_file_system.h"

using namespace olt;
using nlohmann::json;

namespace {

// Units named u0, u1, ... whose record is {"input": value, "boxes": {...}}; unit 2 is not made.
class CountingWork : public UnitWork {
 public:
  explicit CountingWork(std::vector<json> records) {
    for (size_t i = 0; i < records.size(); ++i) {
      if (i == 2) {
        units_.emplace_back();
        records_.emplace_back();
        continue;
      }
      records_.push_back(records[i].dump());
      units_.push_back(unit_of("u" + std::to_string(i), records_.back()));
    }
  }
  const std::vector<std::optional<Unit>>& units() const override { return units_; }
  std::string record(size_t i) const override { return records_.at(i); }
  bool run(size_t i, ArtifactWriter& out) const override {
    out.write("value.txt", records_[i]);
    const std::lock_guard<std::mutex> lock(mutex_);
    ran_.push_back(i);
    return in_place_ && i % 2 == 1;  // "worked in place": the odd units
  }
  void work_in_place_on_odd_units() { in_place_ = true; }
  void take(size_t i, const Artifact& entry, ArtifactWriter&) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    taken_[i] = entry;
  }
  json assemble(const StageContext&, ArtifactWriter&) override { return json::object(); }
  /// The entries taken, by position.
  const std::map<size_t, Artifact>& taken() const { return taken_; }
  std::vector<size_t> ran() const {
    std::vector<size_t> sorted = ran_;
    std::sort(sorted.begin(), sorted.end());
    return sorted;
  }

 private:
  std::vector<std::optional<Unit>> units_;
  std::vector<std::string> records_;
  mutable std::mutex mutex_;
  mutable std::vector<size_t> ran_;
  std::map<size_t, Artifact> taken_;
  bool in_place_ = false;
};

std::vector<json> records(int count, const std::string& box_digest = "b") {
  std::vector<json> list;
  for (int i = 0; i < count; ++i) list.push_back({{"input", i}, {"boxes", {{"box1", box_digest}}}});
  return list;
}

const UnitWords kWords{"frame", "label", "labeled", "boxes", "box", "seeing"};

}  // namespace

TEST_CASE("units: each runs once into an entry of its own, then is found - entries hold what the unit wrote") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  ArtifactFolder out("/artifact", files);
  CountingWork work(records(5));
  CHECK(run_units(work, kWords, store, out) == json{{"frames_labeled", 4}, {"frames_reused", 0}});
  CHECK(work.ran() == std::vector<size_t>{0, 1, 3, 4});
  // Each entry was taken once as it came, none for the unit not made.
  REQUIRE(work.taken().size() == 4);
  CHECK(!work.taken().count(2));
  CHECK(files.read(work.taken().at(3).dir / "value.txt") == json({{"input", 3}, {"boxes", {{"box1", "b"}}}}).dump());
  // The records, by unit name, as one JSON object: a record a line, in its compact text, sorted by name.
  const std::string records_text = files.read("/artifact/frames.json");
  const json written = json::parse(records_text);
  CHECK(records_text == "{\n \"u0\": " + written["u0"].dump() + ",\n \"u1\": " + written["u1"].dump() +
                            ",\n \"u3\": " + written["u3"].dump() + ",\n \"u4\": " + written["u4"].dump() + "\n}\n");
  CHECK(written.size() == 4);
  CHECK(written["u3"] == json({{"input", 3}, {"boxes", {{"box1", "b"}}}}));

  CountingWork again(records(5));
  CHECK(run_units(again, kWords, store, out) == json{{"frames_labeled", 0}, {"frames_reused", 4}});
  CHECK(again.ran().empty());
  REQUIRE(again.taken().size() == 4);
  CHECK(again.taken().at(3).key == work.taken().at(3).key);
  // The key is the unit word and the SHA-256 of the record's compact text: caches made before stay valid.
  CHECK(unit_key(*work.units()[3], kWords) == "frame-" + sha256_hex(records(5)[3].dump()));
  // Units are committed without a sync: the run syncs the cache once before it returns (see the
  // power loss in runner_memory_test.cpp).
  CHECK(files.syncs() == 0);
  CHECK(files.list("/cache/tmp").empty());
}

TEST_CASE("units: records of several megabytes are written in pieces that make one document - a record a line") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  ArtifactFolder out("/artifact", files);
  std::vector<json> big;
  for (int i = 0; i < 400; ++i) big.push_back({{"input", i}, {"boxes", {{"box1", std::string(8000, 'a' + i % 26)}}}});
  CountingWork work(big);
  run_units(work, kWords, store, out);
  json expected = json::object();
  for (size_t i = 0; i < big.size(); ++i)
    if (i != 2) expected["u" + std::to_string(i)] = big[i];
  const std::string text = files.read("/artifact/frames.json");
  CHECK(text.size() > (3u << 20));
  CHECK(json::parse(text) == expected);
  CHECK(std::count(text.begin(), text.end(), '\n') == static_cast<long>(expected.size()) + 2);  // "{", each record, "}"
}

TEST_CASE("units: the log counts the units that worked in place, from what the process kept of their last run") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  ArtifactFolder out("/artifact", files);
  CountingWork first(records(5));
  CHECK(run_units(first, kWords, store, out) ==
        json{{"frames_labeled", 4}, {"frames_reused", 0}});  // none started from kept state: no count
  CountingWork edited(records(5, "c"));
  edited.work_in_place_on_odd_units();
  CHECK(run_units(edited, kWords, store, out) ==
        json{{"frames_labeled", 4}, {"frames_reused", 0}, {"frames_in_place", 2}});  // u1 and u3
}

TEST_CASE("units: a shard runs only every count-th unit - a merge names the units no shard left, with their shard") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  const CountingWork shard1(records(6));
  CHECK(run_shard_units(shard1, kWords, store, Shard{1, 2}) == json{{"frames_labeled", 3}, {"frames_reused", 0}});
  CHECK(shard1.ran() == std::vector<size_t>{1, 3, 5});
  try {
    check_units_cached(shard1, kWords, store, "labels", 2);
    FAIL("units 0 and 4 are missing");
  } catch (const ShardsIncomplete& e) {
    CHECK_THAT(e.what(), Catch::Contains("2 unit(s) of stage 'labels' are not in the cache: u0 (shard 0/2), "
                                         "u4 (shard 0/2)"));
  }
  const CountingWork shard0(records(6));
  CHECK(run_shard_units(shard0, kWords, store, Shard{0, 2}) == json{{"frames_labeled", 2}, {"frames_reused", 0}});
  CHECK_NOTHROW(check_units_cached(shard0, kWords, store, "labels", 2));
}

TEST_CASE("units: the plan counts units to run and says why, against the records of the previous run") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  const fs::path previous_dir = "/previous";
  ArtifactFolder out(previous_dir, files);
  CountingWork first(records(5));
  run_units(first, kWords, store, out);
  Artifact previous;
  previous.dir = previous_dir;
  previous.files.add("frames.json", Digest(), 0);

  std::vector<json> edited = records(5);
  edited[0]["input"] = 100;              // its input changed
  edited[1]["boxes"]["box1"] = "moved";  // a box it sees moved
  edited[3]["boxes"]["box2"] = "new";    // a box came into view
  edited[4]["boxes"] = json::object();   // its box left the view
  const json plan = explain_units(CountingWork(edited), kWords, store, previous);
  CHECK(plan["frames_to_label"] == 4);
  CHECK(plan["frames_reused"] == 0);
  CHECK(plan["causes"] == json{{"input changed", 1}});
  CHECK(plan["frames_seeing_changed_box"] == json{{"box1", 2}, {"box2", 1}});
  CHECK(plan["text"] == "4 of 4 frames to label; 1: input changed; frames seeing changed box box1 (2), box2 (1)");
}

TEST_CASE("record changes: parts compared whole or member by member - stage reasons name nested params by path") {
  const json before = {{"kind", "poses"},
                       {"version", 9},
                       {"params", {{"method", "registration"}, {"registration", {{"solver", {{"method", "gicp"}}}}}}},
                       {"inputs", {{"source", "d1"}}},
                       {"files", {{"/a.txt", "x"}, {"/b.txt", "y"}}}};
  json now = before;
  now["files"]["/b.txt"] = "z";
  now["files"]["/c.txt"] = "w";
  const RecordChange change = diff_records(now, before, {"params", "inputs", "files"});
  CHECK(change.parts.empty());
  CHECK(change.members.at("files") == std::vector<std::string>{"/b.txt", "/c.txt"});

  StageDecl stage;
  stage.id = "poses";
  stage.inputs = {{"source", "src"}};
  CHECK(rerun_reason(stage, now, std::nullopt) == "never run");
  CHECK(rerun_reason(stage, now, before) == "file /b.txt and 1 other files changed");
  json params = before;
  params["params"]["registration"]["solver"]["method"] = "icp";
  CHECK(rerun_reason(stage, params, before) == "params changed: registration.solver.method");
  json input = before;
  input["inputs"]["source"] = "d2";
  CHECK(rerun_reason(stage, input, before) == "input src changed");
  json version = params;
  version["version"] = 10;
  CHECK(rerun_reason(stage, version, before) == "stage kind version changed");
  CHECK(rerun_reason(stage, before, before) == "not in the cache");
}

TEST_CASE(
    "pieces: bytes a stage remembers are made once per record, found after, made again when damaged - kept by olt "
    "watch") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  FileDigests digests("/cache/file-digests.json", files);
  Job job;
  StageDecl decl{"report", "report", {}, json::object(), {}, ""};
  const std::map<std::string, StageInput> inputs;
  const StageKind kind = make_stage_kind({"report", nullptr, {}, {}, nullptr}, 5, nullptr, nullptr);
  const StageContext context = stage_context(job, decl, inputs, digests, &store, &kind);
  int made = 0;
  const auto make = [&made] {
    ++made;
    return std::string("picture bytes");
  };
  const json record = {{"picture", 1}, {"scene", "abc"}};
  CHECK(context.memo(record, make) == "picture bytes");
  CHECK(context.memo(record, make) == "picture bytes");
  CHECK(made == 1);
  CHECK(context.memo({{"picture", 1}, {"scene", "abd"}}, make) == "picture bytes");
  CHECK(made == 2);  // another record
  // The bytes damaged in place (same size): not taken, made again, and the entry mended.
  const std::string key = "piece-" + sha256_hex(json({{"kind", "report"}, {"version", 5}, {"piece", record}}).dump());
  files.write(artifact_dir("/cache/objects", key) / "bytes", "PICTURE bytes");
  CHECK(context.memo(record, make) == "picture bytes");
  CHECK(made == 3);
  CHECK(context.memo(record, make) == "picture bytes");
  CHECK(made == 3);
  CHECK(store.verify().problems.empty());
  // Another version of the kind draws anew; without a store (olt plan's light stages run aside),
  // made every time.
  const StageKind next = make_stage_kind({"report", nullptr, {}, {}, nullptr}, 6, nullptr, nullptr);
  stage_context(job, decl, inputs, digests, &store, &next).memo(record, make);
  CHECK(made == 4);
  const StageContext plain = stage_context(job, decl, inputs, digests);
  plain.memo(record, make);
  CHECK(made == 5);
  // A process that keeps memory (olt watch) keeps the bytes it read or made, by their digest: damaged
  // in place on disk since (the same size), they are not read again; a file gone is read, and its
  // bytes made again; one that keeps nothing reads them, finds them damaged, and makes them again.
  const auto bytes_of = [](const json& r) {
    return artifact_dir("/cache/objects",
                        "piece-" + sha256_hex(json({{"kind", "report"}, {"version", 5}, {"piece", r}}).dump())) /
           "bytes";
  };
  const json drawn = {{"picture", 2}};
  {
    test::KeepingMemory keeping;
    CHECK(context.memo(record, make) == "picture bytes");  // read
    files.write(bytes_of(record), "PICTURE bytes");
    CHECK(context.memo(record, make) == "picture bytes");
    CHECK(made == 5);
    CHECK(context.memo(drawn, make) == "picture bytes");  // made
    CHECK(made == 6);
    files.write(bytes_of(drawn), "PICTURE bytes");
    CHECK(context.memo(drawn, make) == "picture bytes");
    CHECK(made == 6);
    files.remove(bytes_of(drawn));
    CHECK(context.memo(drawn, make) == "picture bytes");
    CHECK(made == 7);
  }
  CHECK(context.memo(record, make) == "picture bytes");
  CHECK(made == 8);
}

TEST_CASE("pieces: the stage's artifact refers to the pieces it used, once each - gc keeps them with it") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  store.mark();
  FileDigests digests("/cache/file-digests.json", files);
  Job job;
  StageDecl decl{"report", "report", {}, json::object(), {}, ""};
  const std::map<std::string, StageInput> inputs;
  const auto run = [](const StageContext& context, ArtifactWriter& out) {
    for (int i = 0; i < 3; ++i)  // the same picture asked for three times, another once
      out.write("page.html", context.memo({{"picture", 1}}, [] { return std::string("one"); }));
    out.write("other.jpg", context.memo({{"picture", 2}}, [] { return std::string("two"); }));
    return json::object();
  };
  const StageKind kind = make_stage_kind({"report", nullptr, {}, {}, nullptr}, 5, nullptr, run);
  const StageContext context = stage_context(job, decl, inputs, digests, &store, &kind);
  json summary;
  const Artifact report = execute(context, kind, "report-key", store, 0, &summary);
  std::vector<std::string> pieces;
  for (const auto& f : report.files)
    if (f.path.rfind("pieces/", 0) == 0) pieces.emplace_back(f.path);
  CHECK(pieces.size() == 2);
  CHECK(store.verify().problems.empty());
  // A piece no artifact refers to goes; the report's stay with it.
  stage_context(job, decl, inputs, digests, &store, &kind).memo({{"picture", 3}}, [] { return std::string("3"); });
  const auto collected = store.collect_garbage({"report-key"}, 0);
  CHECK(collected.removed == 1);
  CHECK(collected.kept == 3);
  for (const auto& p : pieces) CHECK(store.find(p.substr(std::string("pieces/").size())));
}

TEST_CASE(
    "units: in olt watch an edit's units made again let their entries of the run before go - an undo checks them") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  ArtifactFolder out("/artifact", files);
  const test::KeepingMemory keeping;  // as olt watch does
  const std::string kept = "unit entries:job:labels";
  CountingWork first(records(5, "b"));
  run_units(first, kWords, store, out, nullptr, kept);
  // Edit after edit, every unit made again: what the process remembers stays the same.
  size_t values = 0;
  for (const std::string box : {"c", "d", "e"}) {
    CountingWork edited(records(5, box));
    run_units(edited, kWords, store, out, nullptr, kept);
    CHECK(edited.ran().size() == 4);
    if (box != "c") CHECK(kept_memory().values == values);
    values = kept_memory().values;
  }
  // The first run's entry of u3 damaged (a file cut short): no longer remembered, it is checked when
  // the edits are undone, and made again; the others are found.
  const fs::path damaged = first.taken().at(3).dir / "value.txt";
  files.write(damaged, files.read(damaged).substr(1));
  CountingWork undone(records(5, "b"));
  CHECK(run_units(undone, kWords, store, out, nullptr, kept) == json{{"frames_labeled", 1}, {"frames_reused", 3}});
  CHECK(undone.ran() == std::vector<size_t>{3});
}

TEST_CASE("units: in olt watch entries a unit still holds stay remembered, where it stayed or moved") {
  test::MemoryFileSystem files;
  const Store store("/cache", files);
  ArtifactFolder out("/artifact", files);
  const test::KeepingMemory keeping;  // as olt watch does
  const std::string kept = "unit entries:job:labels";
  std::vector<json> list = records(5, "b");
  CountingWork first(list);
  run_units(first, kWords, store, out, nullptr, kept);
  // u0's and u1's records swapped (their entries held at each other's position), u4's edited.
  std::swap(list[0], list[1]);
  list[4]["boxes"]["box1"] = "c";
  CountingWork edited(list);
  run_units(edited, kWords, store, out, nullptr, kept);
  CHECK(edited.ran() == std::vector<size_t>{4});
  // The entries of u0 (moved) and u3 (in place) damaged: still remembered, they are found without a
  // check of their files (an entry forgotten would be checked and made again, as in the test above).
  for (const size_t i : {size_t{0}, size_t{3}}) {
    const fs::path damaged = first.taken().at(i).dir / "value.txt";
    files.write(damaged, files.read(damaged).substr(1));
  }
  CountingWork again(list);
  CHECK(run_units(again, kWords, store, out, nullptr, kept) == json{{"frames_labeled", 0}, {"frames_reused", 4}});
  CHECK(again.ran().empty());
}
