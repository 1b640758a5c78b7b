// The job runner on a file system in memory, with made-up stage kinds: a second run finds
// everything; an edit re-runs what it touches and no more (a stage whose output did not change stops
// the re-runs below it); shards and their merge give the plain run's bytes; a disk that fills up at
// any write of a run loses nothing (the next run gives the clean run's output and the cache verifies),
// and neither does a power loss.
#include <tbb/task_arena.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <functional>
#include <optional>
#include <set>

#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/runtime/runner.h"
#include "support/keeping_memory.h"
#include "support/memory_file_system.h"
#include "support/rendezvous.h"

using namespace olt;
using namespace olt::test;
using nlohmann::json;

namespace {

// Runs of each kind, counted by the kinds' functions.
struct Counts {
  int numbers = 0, total = 0;
  std::atomic<int> squares{0};        // units run on several threads
  std::atomic<bool>* stop = nullptr;  // set by the square unit numbered `stop_at` (a signal, there)
  int stop_at = 0;
  std::atomic<int> after_stop{0};  // squares that began with `stop` already set
};

// "numbers" writes 1..count (its `label` changes its key, not its output); "total" sums them.
StageKind numbers_kind(Counts& counts) {
  return make_stage_kind({"numbers", nullptr, {}, {}, nullptr}, 1, nullptr,
                         [&counts](const StageContext& c, ArtifactWriter& out) {
                           ++counts.numbers;
                           std::string text;
                           for (int i = 1; i <= c.stage.params.at("count").get<int>(); ++i)
                             text += std::to_string(i) + "\n";
                           out.write("numbers.txt", text);
                           out.publish("numbers.txt", "numbers.txt", "test");
                           return json::object();
                         });
}

std::vector<int> numbers_of(const FileSystem& files, const StageContext& c) {
  std::vector<int> numbers;
  const std::string text = files.read(c.need("numbers").artifact.dir / "numbers.txt");
  for (size_t at = 0, end; (end = text.find('\n', at)) != std::string::npos; at = end + 1)
    numbers.push_back(std::stoi(text.substr(at, end - at)));
  return numbers;
}

StageKind total_kind(const FileSystem& files, Counts& counts) {
  StageKind kind = make_stage_kind({"total", nullptr, {"numbers"}, {}, nullptr}, 1, nullptr,
                                   [&files, &counts](const StageContext& c, ArtifactWriter& out) {
                                     ++counts.total;
                                     int sum = 0;
                                     for (int n : numbers_of(files, c)) sum += n;
                                     out.write("total.txt", std::to_string(sum));
                                     out.publish("total.txt", "total.txt", "test");
                                     return json{{"total", sum}};
                                   });
  return kind;
}

// "squares": one unit per number, each writing its square; assembled into squares/<n>.txt.
class Squares : public UnitWork {
 public:
  Squares(const std::vector<int>& numbers, Counts& counts) : counts_(counts) {
    for (int n : numbers) units_.push_back(unit_of(std::to_string(n), json{{"n", n}}.dump()));
  }
  const std::vector<std::optional<Unit>>& units() const override { return units_; }
  std::string record(size_t i) const override { return json{{"n", std::stoi(units_[i]->name)}}.dump(); }
  bool run(size_t i, ArtifactWriter& out) const override {
    if (counts_.stop && *counts_.stop) ++counts_.after_stop;
    const int n = json::parse(record(i)).at("n");
    out.write("square.txt", std::to_string(n * n));
    ++counts_.squares;
    if (counts_.stop && n == counts_.stop_at) *counts_.stop = true;
    return false;
  }
  void take(size_t i, const Artifact& entry, ArtifactWriter& out) override {
    out.refer("squares/" + units_[i]->name + ".txt", entry, "square.txt");
  }
  json assemble(const StageContext&, ArtifactWriter& out) override {
    for (const auto& unit : units_) {
      const std::string file = "squares/" + unit->name + ".txt";
      out.publish(file, file, "test");
    }
    return json{{"squares", units_.size()}};
  }

 private:
  std::vector<std::optional<Unit>> units_;
  Counts& counts_;
};

StageKind squares_kind(const FileSystem& files, Counts& counts) {
  StageKind kind = make_stage_kind({"squares", nullptr, {"numbers"}, {}, nullptr}, 1, nullptr, nullptr);
  kind.units = [&files, &counts](const StageContext& c) -> std::unique_ptr<UnitWork> {
    return std::make_unique<Squares>(numbers_of(files, c), counts);
  };
  kind.unit_words = {"square", "square", "squared", "", "", ""};
  return kind;
}

StageDecl stage(const std::string& id, const std::string& kind, json params,
                std::map<std::string, std::string> inputs = {}) {
  StageDecl s;
  s.id = id;
  s.kind = kind;
  s.params = std::move(params);
  for (const auto& [input_kind, from] : inputs) s.needs.push_back(from);
  s.inputs = std::move(inputs);
  return s;
}

struct World {
  MemoryFileSystem files;
  Counts counts;
  std::vector<StageKind> kinds{numbers_kind(counts), total_kind(files, counts), squares_kind(files, counts)};
  Job job;

  World() {
    job.file = "/jobs/job.yaml";
    job.output = "/out";
    job.cache = "/cache";
    job.stages = {stage("numbers", "numbers", {{"count", 4}, {"label", "a"}}),
                  stage("total", "total", json::object(), {{"numbers", "numbers"}}),
                  stage("squares", "squares", json::object(), {{"numbers", "numbers"}})};
  }
  RunOptions options() {
    RunOptions o;
    o.env.files = &files;
    o.env.kinds = &kinds;
    return o;
  }
  std::vector<StageStatus> run() { return run_job(job, options()); }
  std::map<std::string, std::string> status(const std::vector<StageStatus>& report) const {
    std::map<std::string, std::string> by_id;
    for (const auto& s : report) by_id[s.id] = s.status;
    return by_id;
  }
  // Every published file with its bytes, and the manifest.
  std::string output() const {
    std::string all;
    for (const auto& path : files.files_below("/out")) all += path + "=" + files.read("/out/" + path) + "\n";
    return all;
  }
};

// The keys of the entries the cache at /cache holds whole (each as the store finds it).
std::set<std::string> entries_found(FileSystem& files) {
  std::set<std::string> found;
  const Store store("/cache", files);
  for (const auto& path : files.files_below("/cache/objects"))
    if (fs::path(path).filename() == ".artifact.json") {
      const std::string key = fs::path(path).parent_path().filename().string();
      if (store.find(key)) found.insert(key);
    }
  return found;
}

// What a run of `w` fails with, as a StageFailure; "" when it does not.
std::string stage_failure(World& w) {
  try {
    w.run();
  } catch (const StageFailure& e) {
    return e.what();
  }
  return "";
}

// What a run that a stop ended says ("stopped ..."); "" when it ran to the end.
std::string stopped_where(const Job& job, const RunOptions& options) {
  try {
    run_job(job, options);
  } catch (const RunStopped& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("runner in memory: a second run finds everything - an edit re-runs what it touches, no more") {
  World w;
  const auto first = w.run();
  CHECK(w.status(first) ==
        std::map<std::string, std::string>{{"numbers", "ran"}, {"total", "ran"}, {"squares", "ran"}});
  CHECK(w.files.read("/out/total.txt") == "10");
  CHECK(w.files.read("/out/squares/3.txt") == "9");
  CHECK(json::parse(w.files.read("/out/manifest.json"))["files"].size() == 6);
  CHECK(w.counts.squares == 4);

  const auto second = w.run();
  CHECK(w.status(second) ==
        std::map<std::string, std::string>{{"numbers", "cached"}, {"total", "cached"}, {"squares", "cached"}});
  CHECK(w.counts.numbers == 1);

  // A new label: numbers runs again, writes the same bytes, so nothing below it runs.
  w.job.stages[0].params["label"] = "b";
  const auto relabeled = w.run();
  CHECK(w.status(relabeled) ==
        std::map<std::string, std::string>{{"numbers", "ran"}, {"total", "cached"}, {"squares", "cached"}});
  CHECK(relabeled[0].reason == "params changed: label");
  CHECK(w.counts.total == 1);

  // One more number: total runs, squares runs only the new unit.
  w.job.stages[0].params["count"] = 5;
  const auto grown = w.run();
  CHECK(w.status(grown) ==
        std::map<std::string, std::string>{{"numbers", "ran"}, {"total", "ran"}, {"squares", "ran"}});
  CHECK(w.counts.squares == 5);
  CHECK(grown[2].summary["squares_reused"] == 4);
  CHECK(w.files.read("/out/total.txt") == "15");
  CHECK(Store("/cache", w.files).verify().problems.empty());
}

TEST_CASE("runner in memory: two shards and their merge publish the bytes of a plain run") {
  World plain;
  plain.run();
  World sharded;
  for (int i = 0; i < 2; ++i) {
    RunOptions o = sharded.options();
    o.shard = Shard{i, 2};
    run_job(sharded.job, o);
    CHECK_FALSE(sharded.files.stat("/out").exists());  // a shard publishes nothing
    // A shard that returned is durable: the units it says it finished survive a power loss.
    sharded.files.lose_power();
    sharded.files.restore_power();
  }
  CHECK(sharded.counts.squares == 4);
  RunOptions env = sharded.options();
  merge_job(sharded.job, env.env);
  CHECK(sharded.counts.squares == 4);  // the merge ran no unit
  CHECK(sharded.output() == plain.output());
}

TEST_CASE("runner in memory: a merge with a shard missing names it and publishes nothing") {
  World w;
  RunOptions o = w.options();
  o.shard = Shard{1, 2};
  run_job(w.job, o);
  CHECK_THROWS_AS(merge_job(w.job, o.env), ShardsIncomplete);
  CHECK_FALSE(w.files.stat("/out").exists());
}

TEST_CASE("runner in memory: a disk that fills up at any write of a run loses nothing") {
  World clean;
  clean.run();
  const std::string expected = clean.output();
  const int64_t writes = clean.files.writes();
  REQUIRE(writes > 20);
  for (int64_t n = 0; n < writes; ++n) {
    World w;
    w.files.fail_writes_after(n);
    CHECK_THROWS(w.run());
    w.files.fail_writes_after(-1);
    INFO("disk full after " << n << " writes");
    // What the failed run stored is durable once it returned: a power loss then takes none of it.
    const std::set<std::string> stored = entries_found(w.files);
    w.files.lose_power();
    w.files.restore_power();
    CHECK(entries_found(w.files) == stored);
    w.run();
    CHECK(w.output() == expected);
    CHECK(Store("/cache", w.files).verify().problems.empty());
  }
}

TEST_CASE("runner in memory: a power loss at any write of a run loses nothing - a run that returned is durable") {
  // The job run, then edited and run again: the power goes during the second run, at each of its
  // writes in turn. Edited to five numbers instead of four (every stage runs, the output changes), or
  // to another label (the first stage runs, nothing to publish). The cache on the output's file
  // system, and on one of its own (synced apart).
  const bool cache_apart = GENERATE(false, true);
  const char* edited = GENERATE("count", "label");
  const auto edit = [&](World& w) {
    json& params = w.job.stages[0].params;
    edited == std::string("count") ? params["count"] = 5 : params["label"] = "b";
  };
  World clean;
  if (cache_apart) clean.files.mount("/cache");
  clean.run();
  edit(clean);
  const int64_t before = clean.files.writes();
  clean.run();
  const std::string expected = clean.output();
  const int64_t writes = clean.files.writes() - before;
  REQUIRE(writes > 5);
  for (int64_t n = 0; n <= writes; ++n) {
    World w;
    if (cache_apart) w.files.mount("/cache");
    w.run();
    edit(w);
    w.files.cut_power_after(n);
    if (n < writes) CHECK_THROWS(w.run());
    if (n == writes) w.run(), w.files.lose_power();  // right after the run returned
    w.files.restore_power();
    INFO("power lost after " << n << " writes of a run after the " << edited << " was edited"
                             << (cache_apart ? ", the cache on a file system of its own" : ""));
    if (n == writes) {  // a run that returned is durable: its output, and every entry it made
      CHECK(w.output() == expected);
      const int numbers = w.counts.numbers, totals = w.counts.total, squares = w.counts.squares;
      for (const auto& [id, status] : w.status(w.run())) CHECK(status == "cached");
      CHECK(w.counts.numbers == numbers);
      CHECK(w.counts.total == totals);
      CHECK(w.counts.squares == squares);
    }
    w.run();
    // What the output holds but the temporaries the run the power took was writing: they are
    // removed once their process is gone (orphaned_temp), and this test's process lives on.
    std::string output;
    for (const auto& path : w.files.files_below("/out"))
      if (path.rfind(".tmp.", 0) != 0) output += path + "=" + w.files.read("/out/" + path) + "\n";
    CHECK(output == expected);
    CHECK(Store("/cache", w.files).verify().problems.empty());
  }
}

TEST_CASE("runner in memory: a stop ends the run at the next unit - nothing published, what it finished durable") {
  // A signal (Slurm at its time limit, Kubernetes stopping a pod, Ctrl-C) while the squares are
  // made: no square starts after it, the run publishes nothing, and what it stored survives a power
  // loss right after; the next run makes only the squares left and publishes the plain run's bytes.
  World plain;
  plain.job.stages[0].params["count"] = 40;
  plain.run();
  const std::string expected = plain.output();

  World w;
  w.job.stages[0].params["count"] = 40;
  std::atomic<bool> stop{false};
  w.counts.stop = &stop;
  w.counts.stop_at = GENERATE(1, 17, 40);  // the order units run in is the threads': any of them
  RunOptions options = w.options();
  options.stop = &stop;
  const std::string what = stopped_where(w.job, options);
  INFO("stopped at square " << w.counts.stop_at << ": " << what);
  const int made = w.counts.squares;
  // Only a square another thread had started as the stop came may begin after it: one per other
  // thread of the pool.
  CHECK(w.counts.after_stop < tbb::this_task_arena::max_concurrency());
  if (what == "stopped before publishing") {  // the last square to start set it
    CHECK(made == 40);
  } else {
    CHECK_THAT(what, Catch::StartsWith("stopped in stage 'squares' (squares) with "));
    CHECK_THAT(what, Catch::EndsWith(" of 40 squares left to square"));
    CHECK(made < 40);
    CHECK(std::stoi(what.substr(what.find(" with ") + 6)) == 40 - made);  // each made, or left
  }
  CHECK(w.files.files_below("/out").empty());
  w.files.lose_power();
  w.files.restore_power();
  w.counts.stop = nullptr;
  w.run();
  CHECK(w.output() == expected);
  CHECK(w.counts.squares == 40);  // the squares made before the stop were found, not made again
  CHECK(w.counts.numbers == 1);
}

TEST_CASE("runner in memory: a shard stopped records nothing finished - the merge names it, a rerun makes the rest") {
  World plain;
  plain.job.stages[0].params["count"] = 40;
  plain.run();
  World w;
  w.job.stages[0].params["count"] = 40;
  RunOptions other = w.options();
  other.shard = Shard{1, 2};
  run_job(w.job, other);  // shard 1/2 finished
  std::atomic<bool> stop{false};
  w.counts.stop = &stop;
  w.counts.stop_at = 9;  // one of shard 0/2's (odd numbers: positions 0, 2, ...)
  RunOptions options = w.options();
  options.shard = Shard{0, 2};
  options.stop = &stop;
  const std::string what = stopped_where(w.job, options);
  INFO(what);
  const int made = w.counts.squares - 20;
  if (what == "stopped before recording the shard finished") {  // square 9 was the last to start
    CHECK(made == 20);
  } else {
    CHECK_THAT(what, Catch::EndsWith(" of 20 squares left to square"));
    CHECK(std::stoi(what.substr(what.find(" with ") + 6)) == 20 - made);
  }
  w.files.lose_power();  // what it made is durable all the same
  w.files.restore_power();
  RunOptions env = w.options();
  CHECK_THROWS_WITH(merge_job(w.job, env.env), Catch::Contains("shard 0/2 of") && !Catch::Contains("1/2"));
  w.counts.stop = nullptr;
  stop = false;
  run_job(w.job, options);
  CHECK(w.counts.squares == 40);  // the squares made before the stop were not made again
  merge_job(w.job, env.env);
  CHECK(w.output() == plain.output());
}

TEST_CASE("runner in memory: a stop set before a stage ends the run there") {
  World w;
  w.run();
  const std::string before = w.output();
  w.job.stages[0].params["count"] = 5;
  const std::atomic<bool> stop{true};
  RunOptions options = w.options();
  options.stop = &stop;
  CHECK_THROWS_WITH(run_job(w.job, options), "stopped before stage 'numbers' (numbers)");
  CHECK(w.counts.numbers == 1);
  CHECK(w.output() == before);

  // Set while the first stage runs (a signal then): the stage finishes, the next does not start.
  std::atomic<bool> during{false};
  w.kinds[0] = make_stage_kind({"numbers", nullptr, {}, {}, nullptr}, 1, nullptr,
                               [&during](const StageContext&, ArtifactWriter& out) {
                                 during = true;
                                 out.write("numbers.txt", "1\n2\n");
                                 return json::object();
                               });
  options.stop = &during;
  CHECK_THROWS_WITH(run_job(w.job, options), "stopped before stage 'total' (total)");
  CHECK(w.output() == before);
  during = false;
  const auto statuses = w.status(run_job(w.job, options));
  CHECK(statuses.at("numbers") == "cached");  // the stage that finished before the stop was kept
}

TEST_CASE("runner in memory: a run syncs once for what it stored and published, once for the output it moved") {
  // Each sync waits for every byte its file system has not yet written, anyone's: a run of `olt
  // watch` on a disk shared with other writers waits as many times as it syncs.
  World w;
  w.run();
  int64_t syncs = w.files.syncs();
  w.run();  // nothing to do
  CHECK(w.files.syncs() == syncs);
  w.job.stages[0].params["label"] = "b";  // a stage runs, to the same output: the cache alone
  w.run();
  CHECK(w.files.syncs() == syncs + 1);
  syncs = w.files.syncs();
  w.job.stages[0].params["count"] = 5;  // every stage runs, the output changes
  w.run();
  CHECK(w.files.syncs() == syncs + 2);  // the cache with the staged changes, then the output
  syncs = w.files.syncs();
  w.files.mount("/cache");
  w.job.stages[0].params["count"] = 6;
  w.run();
  CHECK(w.files.syncs() == syncs + 3);  // the cache's own file system beside the output's
}

TEST_CASE("runner in memory: where the output's files are clones of the cache's, the cache is synced before") {
  // XFS writes a clone's source to the disk before it clones it, a file at a time: one sync of the
  // cache first writes them all at once. Only where the first file came as a clone.
  World w;
  w.files.clone_copies();
  w.run();
  int64_t syncs = w.files.syncs(), unsynced = w.files.clones_of_unsynced();
  w.job.stages[0].params["count"] = 5;  // the output changes: every stage runs
  w.run();
  CHECK(w.files.syncs() == syncs + 3);                  // the cache, the cache with the staged changes, the output
  CHECK(w.files.clones_of_unsynced() == unsynced + 1);  // the first file's: every other after the sync
  syncs = w.files.syncs();
  unsynced = w.files.clones_of_unsynced();
  w.files.mount("/cache");  // two file systems: copies, not clones
  w.job.stages[0].params["count"] = 6;
  w.run();
  CHECK(w.files.syncs() == syncs + 3);  // the cache's own file system beside the output's
  CHECK(w.files.clones_of_unsynced() == unsynced);
}

TEST_CASE("runner in memory: a sync that fails fails the run - what it stored unsynced is made again by the next") {
  // A sync fails as a disk's write-back error does: what the run stored since its last sync may not
  // be on the disk as it reads now, so it goes. The first sync of the run (the cache, with the staged
  // changes where there are any), or the second (the output, once its files are moved: the cache is
  // durable by then, and the publish is finished by the next run from its journal). Where the files
  // are clones, the cache is synced alone first: then the second is the staged changes' (the cache
  // durable, nothing published) and the third the output's.
  const char* edited = GENERATE("count", "label");
  const bool clones = GENERATE(false, true);
  const int failing = GENERATE(0, 1, 2);
  const bool publishes = edited == std::string("count");
  if (failing >= 1 && !publishes) return;  // a run with nothing to publish syncs once
  if (failing == 2 && !clones) return;     // twice without clones
  const auto edit = [&](World& w) {
    json& params = w.job.stages[0].params;
    publishes ? params["count"] = 5 : params["label"] = "b";
  };
  World clean;
  clean.run();
  const std::string before = clean.output();
  edit(clean);
  clean.run();
  World w;
  if (clones) w.files.clone_copies();
  w.run();
  edit(w);
  w.files.fail_sync_after(failing);
  INFO("sync " << failing << " of a run after the " << edited << " was edited fails" << (clones ? ", clones" : ""));
  CHECK_THROWS_AS(w.run(), SyncFailed);
  if (failing == 0 || (clones && failing == 1)) CHECK(w.output() == before);  // nothing published
  const int numbers = w.counts.numbers;
  for (const auto& [id, status] : w.status(w.run()))
    CHECK(status == (failing == 0 && (id == "numbers" || publishes) ? "ran" : "cached"));
  CHECK(w.counts.numbers == numbers + (failing == 0 ? 1 : 0));
  CHECK(w.output() == clean.output());
  CHECK(Store("/cache", w.files).verify().problems.empty());
}

TEST_CASE("runner in memory: a damaged cache entry is named, removed, and computed anew by the next run") {
  World clean;
  clean.run();
  World w;
  w.run();
  std::string damaged;
  for (const auto& path : w.files.files_below("/cache/objects"))
    if (fs::path(path).filename() == "numbers.txt") damaged = "/cache/objects/" + path;
  REQUIRE(!damaged.empty());
  w.files.write(damaged, "9\n2\n3\n4\n");  // same size, other bytes
  w.files.remove("/out");                  // so that publishing copies it again
  CHECK_THAT(stage_failure(w), Catch::Contains("stage 'numbers'") && Catch::Contains("removed from the cache"));
  CHECK_FALSE(w.files.stat("/out/manifest.json").exists());
  w.run();
  CHECK(w.counts.numbers == 2);
  CHECK(w.output() == clean.output());
}

TEST_CASE("runner in memory: what a killed run left half-made in the cache is removed by the next run") {
  World w;
  const std::string here = host_name(), alive = std::to_string(::getpid());
  w.files.write("/cache/tmp/.tmp.k1." + here + ".999999999.0/numbers.txt", "half");  // a dead process's
  w.files.write("/cache/tmp/.tmp.k2." + here + "." + alive + ".0/numbers.txt", "in the making");
  w.files.write("/cache/tmp/.tmp.k3.other-machine.999999999.0/numbers.txt", "another machine's");
  w.run();
  CHECK(w.files.list("/cache/tmp") ==
        std::vector<std::string>{".tmp.k2." + here + "." + alive + ".0", ".tmp.k3.other-machine.999999999.0"});
}

TEST_CASE("runner in memory: an entry whose list was let go and is gone by publishing is named, nothing published") {
  // The run lets go of the file list of "numbers", which it made, after its last reader ("vandal",
  // not the job's last stage), and reads it again to publish; here that reader removes the entry's
  // metadata in between.
  World w;
  const auto kind = [&w](const std::string& name, std::vector<std::string> reads, bool vandal) {
    return make_stage_kind({name, nullptr, std::move(reads), {}, nullptr}, 1, nullptr,
                           [&w, vandal](const StageContext& c, ArtifactWriter& out) {
                             if (vandal) w.files.remove(c.need("numbers").artifact.dir / ".artifact.json");
                             out.write("done.txt", "done");
                             return json::object();
                           });
  };
  w.kinds.push_back(kind("vandal", {"numbers"}, true));
  w.kinds.push_back(kind("idle", {}, false));
  w.job.stages.push_back(stage("vandal", "vandal", json::object(), {{"numbers", "numbers"}}));
  w.job.stages.push_back(stage("idle", "idle", json::object()));
  CHECK_THAT(stage_failure(w), Catch::Contains("stage 'numbers'") && Catch::Contains("removed during the run"));
  CHECK_FALSE(w.files.stat("/out/manifest.json").exists());
  w.job.stages.resize(3);
  World clean;
  clean.run();
  w.run();  // the next run computes it again
  CHECK(w.output() == clean.output());
}

TEST_CASE("runner in memory: a stage that looks up a few files of a list let go is given them alone, then they go") {
  // "squares" refers to its four units' files; "whole" reads its whole list, "peek" declares it looks
  // up only squares/2.txt. After its last whole reader the run keeps only what a later stage looks
  // up, nothing after that; publishing reads the whole list again. Orders: peek after whole and
  // before another stage, peek last, peek before whole (given the whole list, still held). Each
  // stage needs the one before it, so that none runs beside another (stage_steps): the lists are let
  // go after each step.
  const auto [order, peek_sees] = GENERATE(table<std::vector<std::string>, size_t>(
      {{{"whole", "peek", "idle"}, 1}, {{"whole", "peek"}, 1}, {{"peek", "whole", "idle"}, 7}}));
  World w;
  size_t peek_saw = 0, whole_saw = 0;
  std::string peeked;
  StageKind peek = make_stage_kind({"peek", nullptr, {"squares"}, {}, nullptr}, 1, nullptr,
                                   [&](const StageContext& c, ArtifactWriter& out) {
                                     const Artifact& squares = c.need("squares").artifact;
                                     peek_saw = squares.files.size();
                                     peeked = w.files.read(squares.path("squares/2.txt"));
                                     out.write("peeked.txt", peeked);
                                     return json::object();
                                   });
  peek.looks_up = {{"squares", [](const ListedFile& f) { return f.path == "squares/2.txt"; }}};
  StageKind whole = make_stage_kind({"whole", nullptr, {"squares"}, {}, nullptr}, 1, nullptr,
                                    [&](const StageContext& c, ArtifactWriter& out) {
                                      whole_saw = c.need("squares").artifact.files.size();
                                      out.write("seen.txt", std::to_string(whole_saw));
                                      return json::object();
                                    });
  w.kinds.push_back(peek);
  w.kinds.push_back(whole);
  w.kinds.push_back(
      make_stage_kind({"idle", nullptr, {}, {}, nullptr}, 1, nullptr, [](const StageContext&, ArtifactWriter& out) {
        out.write("done.txt", "done");
        return json::object();
      }));
  for (const std::string& id : order) {
    const std::string before = w.job.stages.back().id;
    w.job.stages.push_back(stage(id, id, json::object(),
                                 id == "idle" ? std::map<std::string, std::string>{}
                                              : std::map<std::string, std::string>{{"squares", "squares"}}));
    w.job.stages.back().needs.push_back(before);
  }
  w.run();
  CHECK(whole_saw == 7);  // the four squares, squares.json, summary.json, publish.json
  CHECK(peek_saw == peek_sees);
  CHECK(peeked == "4");
  for (int n = 1; n <= 4; ++n)
    CHECK(w.files.read("/out/squares/" + std::to_string(n) + ".txt") == std::to_string(n * n));
  CHECK(json::parse(w.files.read("/out/manifest.json"))["files"].size() == 6);

  // A second run finds everything: whole lists, nothing cut (the stages do not run).
  peek_saw = whole_saw = 0;
  CHECK(w.status(w.run()).at("peek") == "cached");
  CHECK(peek_saw == 0);
}

TEST_CASE("runner in memory: a cache file gone before publishing is named with its stage, its entry removed") {
  // The run lets the list of "squares" go after its last reader ("vandal", not the job's last stage)
  // and reads it again to publish, without looking for each file; here that reader removes the file
  // of a unit "squares" refers to.
  World w;
  w.kinds.push_back(make_stage_kind({"vandal", nullptr, {"squares"}, {}, nullptr}, 1, nullptr,
                                    [&w](const StageContext& c, ArtifactWriter& out) {
                                      const Artifact& squares = c.need("squares").artifact;
                                      w.files.remove(squares.path("squares/3.txt"));
                                      out.write("done.txt", "done");
                                      return json::object();
                                    }));
  w.kinds.push_back(
      make_stage_kind({"idle", nullptr, {}, {}, nullptr}, 1, nullptr, [](const StageContext&, ArtifactWriter& out) {
        out.write("done.txt", "done");
        return json::object();
      }));
  w.job.stages.push_back(stage("vandal", "vandal", json::object(), {{"squares", "squares"}}));
  w.job.stages.push_back(stage("idle", "idle", json::object()));
  CHECK_THAT(stage_failure(w), Catch::Contains("stage 'squares'") && Catch::Contains("is gone") &&
                                   Catch::Contains("removed from the cache"));
  CHECK_FALSE(w.files.stat("/out/manifest.json").exists());
  w.job.stages.resize(3);
  World clean;
  clean.run();
  w.run();  // the next run computes the unit again
  CHECK(w.output() == clean.output());
}

namespace {

// A stage kind that reads the numbers, runs `body`, and writes `<name>.txt` holding `name`.
StageKind reader_kind(const std::string& name, std::function<void()> body) {
  return make_stage_kind({name, nullptr, {"numbers"}, {}, nullptr}, 1, nullptr,
                         [name, body](const StageContext&, ArtifactWriter& out) {
                           body();
                           out.write(name + ".txt", name);
                           out.publish(name + ".txt", name + ".txt", "test");
                           return json::object();
                         });
}

// The world with two more stages after the numbers, `left` and `right`, reading them and not each other.
void add_two_readers(World& w, std::function<void()> left, std::function<void()> right) {
  w.kinds.push_back(reader_kind("left", std::move(left)));
  w.kinds.push_back(reader_kind("right", std::move(right)));
  w.job.stages = {stage("numbers", "numbers", {{"count", 4}, {"label", "a"}}),
                  stage("left", "left", json::object(), {{"numbers", "numbers"}}),
                  stage("right", "right", json::object(), {{"numbers", "numbers"}})};
}

}  // namespace

TEST_CASE("runner in memory: where the process keeps memory, stages that read none of each other run side by side") {
  // Each of the two waits for the other to begin: the run ends well only if they ran at once.
  if (tbb::this_task_arena::max_concurrency() < 2) {
    WARN("one thread in this process: stages run one after the other, nothing to check");
    return;
  }
  Rendezvous rendezvous;
  const auto meet = [&](int side) {
    if (!rendezvous.meet(side)) throw std::runtime_error("the other stage did not begin");
  };
  World w;
  add_two_readers(
      w, [&] { meet(0); }, [&] { meet(1); });
  const KeepingMemory keeping;
  const auto report = w.run();
  REQUIRE(report.size() == 3);  // in the job's order
  CHECK(report[1].id == "left");
  CHECK(report[2].id == "right");
  CHECK(w.files.read("/out/left.txt") == "left");
  CHECK(w.files.read("/out/right.txt") == "right");
}

TEST_CASE("runner in memory: side by side or one after the other, a run publishes the same bytes") {
  const auto output = [](bool keeping) {
    World w;
    add_two_readers(
        w, [] {}, [] {});
    std::optional<KeepingMemory> keep;
    if (keeping) keep.emplace();
    w.run();
    return w.output();
  };
  CHECK(output(true) == output(false));
}

TEST_CASE("runner in memory: a stage failing beside another ends the run after the other is in the cache") {
  // The first failure in the job's order is the run's; the stage beside it ends into the cache and
  // is found there by the next run.
  const std::string failing = GENERATE(as<std::string>{}, "left", "right");
  bool fail = true;
  World w;
  const auto body = [&](const std::string& name) {
    return [&fail, &failing, name] {
      if (fail && name == failing) throw std::runtime_error(name + " cannot go on");
    };
  };
  add_two_readers(w, body("left"), body("right"));
  const KeepingMemory keeping;
  try {
    w.run();
    FAIL("the run did not fail");
  } catch (const StageFailure& e) {
    CHECK(e.stage() == failing);
    CHECK_THAT(e.what(), Catch::Contains(failing + " cannot go on"));
  }
  fail = false;
  const auto again = w.status(w.run());
  CHECK(again.at(failing) == "ran");
  CHECK(again.at(failing == "left" ? "right" : "left") == "cached");
}

TEST_CASE("runner in memory: two stages failing side by side: the run ends with the first in the job's order") {
  World w;
  add_two_readers(
      w, [] { throw std::runtime_error("left fails"); }, [] { throw std::runtime_error("right fails"); });
  const KeepingMemory keeping;
  try {
    w.run();
    FAIL("the run did not fail");
  } catch (const StageFailure& e) {
    CHECK(e.stage() == "left");
  }
}
