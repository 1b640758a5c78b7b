// Incremental relabelling: after one box moves, only the frames that see it (before or after) are
// labeled again, `olt plan` says how many and why, and the result equals a run from scratch.
#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "olt/cache/store.h"
#include "olt/core/process_memory.h"
#include "olt/runtime/runner.h"
#include "support/keeping_memory.h"
#include "support/probe_job.h"
#include "support/temp_dir.h"

using namespace olt::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

json labels_detail(const fs::path& job) {
  const auto plan = run_olt("plan --json " + job.string());
  REQUIRE(plan.exit_code == 0);
  INFO(plan.out);
  const json parsed = json::parse(plan.out);
  for (const auto& s : parsed["stages"])
    if (s["id"] == "labels") {
      REQUIRE(s.contains("detail"));
      return s["detail"];
    }
  FAIL("no labels stage in the plan");
  return json();
}

// The artifact the last run of `stage` made in the cache, by the cache's log.
olt::Artifact last_made(const fs::path& cache, const std::string& stage) {
  std::string key;
  std::istringstream log(read_text(cache / "log.jsonl"));
  for (std::string line; std::getline(log, line);) {
    const json entry = json::parse(line);
    if (entry.value("stage", "") == stage && entry.contains("key")) key = entry["key"];
  }
  REQUIRE(!key.empty());
  const auto artifact = olt::Store(cache).find(key);
  REQUIRE(artifact);
  return *artifact;
}

// The files under `folder` of the output, by name.
std::map<std::string, std::string> files_in(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    if (e.is_regular_file()) files[e.path().lexically_relative(folder).generic_string()] = read_text(e.path());
  return files;
}

}  // namespace

TEST_CASE("moving one box relabels only the frames that see it - plan says which - same bytes as from scratch") {
  TempDir dir;
  // The synthetic room's boxes are all in every frame's view; the probe box is seen from the end of
  // the camera's arc only.
  json boxes = write_probe_job(dir.path());
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  const auto seen_before = boxes_seen(dir / "out");
  REQUIRE(seen_before.size() == 12);

  // The box seen by the fewest frames (but some).
  std::map<std::string, int> frames_of;
  for (const auto& [frame, boxes] : seen_before)
    for (const auto& b : boxes) ++frames_of[b];
  std::string moved;
  for (const auto& [box, n] : frames_of)
    if (moved.empty() || n < frames_of[moved]) moved = box;
  INFO("moved box " << moved << ", seen in " << frames_of[moved] << " of 12 frames");
  REQUIRE(frames_of[moved] < 12);

  for (auto& b : boxes["boxes"])
    if (b["id"] == moved) b["center"][2] = b["center"][2].get<double>() + 0.01;
  write_text(dir / "boxes.json", boxes.dump(1));

  const json detail = labels_detail(dir / "job.yaml");
  const int to_label = detail["frames_to_label"];
  CHECK(to_label + detail["frames_reused"].get<int>() == 12);
  CHECK(to_label < 12);
  CHECK(detail["frames_seeing_changed_box"] == json{{moved, to_label}});
  CHECK(detail["causes"].empty());

  const auto run = run_olt("run " + (dir / "job.yaml").string());
  REQUIRE(run.exit_code == 0);
  // Afresh: `olt run` keeps nothing in memory to start them from (olt watch does: the next test).
  CHECK_THAT(run.err, Catch::Contains("(" + std::to_string(to_label) + " relabeled, " + std::to_string(12 - to_label) +
                                      " unchanged)"));
  // Every frame that lists the box, before or after the move, was among those relabeled.
  const auto seen_after = boxes_seen(dir / "out");
  int listing = 0;
  for (const auto& [frame, boxes_before] : seen_before)
    listing += boxes_before.count(moved) || seen_after.at(frame).count(moved);
  CHECK(listing <= to_label);
  CHECK(listing > 0);

  // The same job from scratch, in a fresh cache, gives the same bytes.
  const std::string incremental = snapshot(dir / "out");
  fs::remove_all(dir / "out");
  fs::remove_all(dir / "cache");
  REQUIRE(run_olt("run " + (dir / "job.yaml").string()).exit_code == 0);
  CHECK(snapshot(dir / "out") == incremental);
}

TEST_CASE("frames relabeled from the labels the process kept, after any edit, are every file labeling afresh gives") {
  TempDir dir;
  json boxes = write_probe_job(dir.path(), "{point_clouds: ply}");
  // A colour camera beside the depth camera, so the colour labels are files of their own.
  std::string job_text = read_text(dir / "job.yaml");
  const std::string calibrate = "calibrate: {kind: calibrate, needs: [source]}";
  REQUIRE(job_text.find(calibrate) != std::string::npos);
  job_text.replace(job_text.find(calibrate), calibrate.size(),
                   "calibrate: {kind: calibrate, needs: [source], params: {sensors: {rgbd: {color_from_depth: [0.025, "
                   "0, 0, 0, 0, 0], color_intrinsics: [150, 150, 80, 60]}}}}");
  job_text += "  dataset: {kind: export, needs: [labels]}\n";  // which keeps its frames' exports too
  write_text(dir / "job.yaml", job_text);
  // As `olt watch` runs the job, edit after edit in one process, keeping the labels it made.
  olt::test::KeepingMemory keeping(size_t{1} << 30);
  const auto run_here = [&] {
    int in_place = 0;
    for (const auto& status : olt::run_job(olt::load_runnable_job(dir / "job.yaml")))
      if (status.summary.is_object()) in_place += status.summary.value("frames_in_place", 0);
    return in_place;
  };
  run_here();
  // `expect_in_place`: whether some frame must be relabeled in place (none: either may be right).
  const auto edit_and_compare = [&](const std::string& edit, std::optional<bool> expect_in_place) {
    INFO("edit: " << edit);
    write_text(dir / "boxes.json", boxes.dump(1));
    const int in_place = run_here();
    if (expect_in_place) CHECK((in_place > 0) == *expect_in_place);
    // The same job and boxes from scratch, in a fresh folder, cache and process.
    TempDir fresh;
    write_text(fresh / "job.yaml", job_text);
    write_text(fresh / "boxes.json", boxes.dump(1));
    REQUIRE(run_olt("run " + (fresh / "job.yaml").string()).exit_code == 0);
    CHECK(snapshot(dir / "out") == snapshot(fresh / "out"));
  };
  auto box = [&](const std::string& id) -> json& {
    for (auto& b : boxes["boxes"])
      if (b["id"] == id) return b;
    FAIL("no box " << id);
    return boxes;
  };
  const std::string first = boxes["boxes"][0]["id"], second = boxes["boxes"][1]["id"];
  box("probe")["center"][0] = box("probe")["center"][0].get<double>() + 0.04;
  const auto boxes_files_before = files_in(dir / "out/dataset/rgbd/boxes");
  edit_and_compare("the probe moved", true);
  // The export wrote again the boxes files whose bytes changed (those of the frames that show the
  // probe), and referred to the others where the run before wrote them.
  const olt::Artifact exported = last_made(dir / "cache", "dataset");
  int written = 0, carried = 0, changed = 0;
  for (const auto& [file, bytes] : files_in(dir / "out/dataset/rgbd/boxes")) {
    const auto listed = exported.file("rgbd/boxes/" + file);
    REQUIRE(listed);
    (listed->in.empty() ? written : carried) += 1;
    CHECK(listed->in.empty() == (bytes != boxes_files_before.at(file)));
    changed += bytes != boxes_files_before.at(file);
  }
  CHECK(changed > 0);
  CHECK(carried > 0);
  CHECK(written == changed);
  // The entry those files were carried from, gone from the cache (removed by hand): the next edit
  // writes them again rather than referring to it.
  std::string origin;
  for (const olt::ListedFile f : exported.files)
    if (!f.in.empty() && f.path.rfind("rgbd/boxes/", 0) == 0) origin = f.in;
  REQUIRE(!origin.empty());
  fs::remove_all(olt::artifact_dir(dir / "cache/objects", origin));
  box("probe")["center"][1] = box("probe")["center"][1].get<double>() + 0.02;
  edit_and_compare("the entry the export's files were carried from removed, the probe moved", true);
  for (const olt::ListedFile f : last_made(dir / "cache", "dataset").files) CHECK(f.in != origin);
  // The export made again under the key of an entry its last run carried files from (the probe moved
  // back; that entry's listing damaged, so the store holds it but cannot read it): those files are
  // written into the new entry, not referred to the one it replaces.
  const std::string key_before = last_made(dir / "cache", "dataset").key;
  const json probe_before = box("probe");
  box("probe")["center"][1] = box("probe")["center"][1].get<double>() + 0.02;
  edit_and_compare("the probe moved", true);
  bool carried_from_before = false;
  for (const olt::ListedFile f : last_made(dir / "cache", "dataset").files) carried_from_before |= f.in == key_before;
  REQUIRE(carried_from_before);
  const fs::path listing = olt::artifact_dir(dir / "cache/objects", key_before) / ".artifact.json";
  write_text(dir / "damaged.json", "{\"digest\": ");
  fs::rename(dir / "damaged.json", listing);  // another file: not the one the process found before
  box("probe") = probe_before;
  edit_and_compare("the probe moved back, the export's entry for it damaged", std::nullopt);
  const olt::Artifact remade = last_made(dir / "cache", "dataset");
  CHECK(remade.key == key_before);
  // Every file it lists is there (not `cache verify`: the entry removed by hand above broke older ones).
  for (const olt::ListedFile f : remade.files) {
    INFO(f.path);
    CHECK(f.in != key_before);
    CHECK(fs::file_size(remade.path(f)) == f.size);
  }
  box(first)["size"][0] = box(first)["size"][0].get<double>() * 1.3;
  box(second)["center"][2] = box(second)["center"][2].get<double>() - 0.03;
  edit_and_compare("two boxes changed", true);
  boxes["boxes"].push_back({{"id", "overlap"},
                            {"label", "probe"},
                            {"center", box(first)["center"]},
                            {"size", {0.2, 0.2, 0.2}},
                            {"rotation", {0, 0, 0, 1}},
                            {"priority", 2}});
  edit_and_compare("a box added over another, with priority", true);
  boxes["boxes"].erase(boxes["boxes"].begin() + 1);
  edit_and_compare("a box removed", true);
  box("probe")["label"] = "aaa_first";                // class ids follow the names: every box's ids change
  edit_and_compare("a class renamed", std::nullopt);  // every box's ids change: each frame in place where they cover
                                                      // under half its image
  box("probe")["center"][1] = box("probe")["center"][1].get<double>() + 0.05;
  edit_and_compare("the probe moved again", true);
  // The job edited so that the labels publish other files (no overlays): the process keeps the
  // stages' publish lists by their digest, so the new list is read, not the one kept.
  const std::string with_clouds = "params: {point_clouds: ply}";
  REQUIRE(job_text.find(with_clouds) != std::string::npos);
  job_text.replace(job_text.find(with_clouds), with_clouds.size(), "params: {point_clouds: ply, overlays: false}");
  write_text(dir / "job.yaml", job_text);
  edit_and_compare("overlays turned off", std::nullopt);
  CHECK_FALSE(fs::exists(dir / "out/labels/rgbd/overlay"));
  // The depth camera's range cut short as the probe moves, then given back with the boxes as they
  // are: which frames see a box is found again for the calibration the run reads, not taken from
  // what the process kept for the one before.
  const std::string color = "color_intrinsics: [150, 150, 80, 60]";
  REQUIRE(job_text.find(color) != std::string::npos);
  const std::string full_range = job_text;
  job_text.replace(job_text.find(color), color.size(), color + ", max_depth_m: 2.0");
  write_text(dir / "job.yaml", job_text);
  box("probe")["center"][0] = box("probe")["center"][0].get<double>() - 0.03;
  edit_and_compare("the depth range cut short, the probe moved", std::nullopt);
  job_text = full_range;
  write_text(dir / "job.yaml", job_text);
  edit_and_compare("the depth range given back", std::nullopt);
  // Labels kept by nobody (another process, or dropped for the budget): labeled afresh.
  olt::keep_in_memory(0);
  olt::keep_in_memory(size_t{1} << 30);
  box("probe")["center"][1] = box("probe")["center"][1].get<double>() + 0.05;
  edit_and_compare("with no labels kept", false);
}

TEST_CASE(
    "in olt watch a stage's entry of the cycle before is let go when it makes another: an undo checks its files") {
  TempDir dir;
  json boxes = write_probe_job(dir.path());
  olt::test::KeepingMemory keeping(size_t{1} << 30);  // as olt watch runs the job, in one process
  const auto labels_status = [&] {
    for (const auto& status : olt::run_job(olt::load_runnable_job(dir / "job.yaml")))
      if (status.id == "labels") return status.status;
    return std::string("missing");
  };
  REQUIRE(labels_status() == "ran");
  const std::string before = snapshot(dir / "out");
  const olt::Artifact first = last_made(dir / "cache", "labels");
  const json annotated = boxes;
  boxes["boxes"][0]["center"][2] = boxes["boxes"][0]["center"][2].get<double>() + 0.01;
  write_text(dir / "boxes.json", boxes.dump(1));
  REQUIRE(labels_status() == "ran");
  // The first entry damaged (a file of another size), then the edit undone: its key again. Had the
  // process kept it as found, it would be taken unchecked ("cached"), its damaged file listed as good.
  write_text(first.dir / "labels.json", "{}\n");
  write_text(dir / "boxes.json", annotated.dump(1));
  CHECK(labels_status() == "ran");
  CHECK(last_made(dir / "cache", "labels").key == first.key);
  CHECK(snapshot(dir / "out") == before);
}

TEST_CASE("in olt watch edit after edit the process keeps as many values: the cycle before's entries let go") {
  TempDir dir;
  json boxes = write_probe_job(dir.path());
  // With the stages that keep per-frame lists and cache pieces (the report's pictures of the box moved).
  std::string job_text = read_text(dir / "job.yaml");
  const std::string annotations = "params: {file: boxes.json}";
  REQUIRE(job_text.find(annotations) != std::string::npos);
  job_text.replace(job_text.find(annotations), annotations.size(), "params: {file: boxes.json, frame: world}");
  write_text(dir / "job.yaml", job_text +
                                   "  scene: {kind: reconstruct, needs: [poses], params: {every: 3}}\n"
                                   "  dataset: {kind: export, needs: [labels]}\n"
                                   "  report: {kind: report, needs: [labels, scene, annotations]}\n");
  olt::test::KeepingMemory keeping(size_t{1} << 30);  // as olt watch runs the job, in one process
  const auto move_probe_and_run = [&] {
    boxes["boxes"][0]["center"][2] = boxes["boxes"][0]["center"][2].get<double>() + 0.01;
    write_text(dir / "boxes.json", boxes.dump(1));
    int relabeled = 0;
    for (const auto& status : olt::run_job(olt::load_runnable_job(dir / "job.yaml")))
      if (status.id == "labels") relabeled = status.summary.value("frames_labeled", 0);
    return relabeled;
  };
  olt::run_job(olt::load_runnable_job(dir / "job.yaml"));
  REQUIRE(move_probe_and_run() > 0);
  const size_t values = olt::kept_memory().values;
  const uint64_t dropped = olt::kept_memory().dropped;  // none: the count is not kept steady by the budget
  // Each edit makes the stages' and the probe's frames' entries again: those of the edit before are
  // no longer remembered, so what the process holds does not grow with the edits.
  for (int edit = 0; edit < 3; ++edit) {
    REQUIRE(move_probe_and_run() > 0);
    CHECK(olt::kept_memory().values == values);
    CHECK(olt::kept_memory().dropped == dropped);
  }
}
