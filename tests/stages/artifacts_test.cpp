// Reading the artifacts stages exchange: a run's stages share the recording and poses they read
// (SharedReads), by the digest their artifact lists for them and the artifact's folder; another
// artifact's are read, not mixed up; without a run's shared reads, each read is afresh. A process
// that keeps memory (olt watch) keeps them for its next run.
#include "olt/stages/artifacts.h"

#include <catch2/catch.hpp>

#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "olt/core/process_memory.h"
#include "support/keeping_memory.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

// An artifact in `dir` holding `file` with `text`, listed with its digest (or not listed).
Artifact artifact_with(const fs::path& dir, const std::string& file, const std::string& text, bool listed = true) {
  fs::create_directories(dir);
  write_file_atomic(dir / file, text);
  Artifact a{"key-" + dir.filename().string(), "digest", dir, {}, dir.parent_path()};
  if (listed) a.files.add(file, Digest(sha256_hex(text)), text.size());
  return a;
}

std::string recording_text(const std::string& id) {
  Recording r;
  r.observations.push_back({id, "cam", 1.5, {"depth/" + id + ".png", Digest(sha256_hex("abc"))}, std::nullopt, 0});
  return to_json(r).dump(1);
}

}  // namespace

TEST_CASE("artifacts: a run's stages share the recording they read - by its listed digest and its folder") {
  TempDir temp;
  const Artifact one = artifact_with(temp / "one", "recording.json", recording_text("a"));
  const Artifact two = artifact_with(temp / "two", "recording.json", recording_text("b"));
  const Artifact same_bytes = artifact_with(temp / "three", "recording.json", recording_text("a"));
  SharedReads shared;

  const auto first = shared_recording({"source", one, &shared});
  CHECK(shared_recording({"source", one, &shared}).get() == first.get());  // not parsed again
  REQUIRE(first->observations.size() == 1);
  CHECK(first->observations[0].id == "a");
  CHECK(first->observations[0].depth.file() == (temp / "one" / "depth/a.png").string());  // in its artifact's folder

  CHECK(shared_recording({"source", two, &shared})->observations[0].id == "b");
  CHECK(shared_recording({"source", one, &shared})->observations[0].id == "a");  // one slot: read again, right
  // The same bytes in another folder: its own paths, not the first folder's.
  CHECK(shared_recording({"source", same_bytes, &shared})->observations[0].depth.file() ==
        (temp / "three" / "depth/a.png").string());
  CHECK(load_recording({"source", one, &shared}).observations[0].id == "a");

  // Cleared (the run's stages are done): let go, read again after.
  const auto kept = shared_recording({"source", one, &shared});
  shared.clear();
  CHECK(kept.use_count() == 1);
  CHECK(shared_recording({"source", one, &shared}).get() != kept.get());
}

TEST_CASE("artifacts: without a run's shared reads, or a digest listed for the file, each read is afresh") {
  TempDir temp;
  const Artifact listed = artifact_with(temp / "one", "recording.json", recording_text("a"));
  const Artifact unlisted = artifact_with(temp / "two", "recording.json", recording_text("c"), false);
  const auto read = shared_recording({"source", listed});
  CHECK(read->observations[0].id == "a");
  CHECK(read.use_count() == 1);  // nothing kept it
  SharedReads shared;
  const auto unlisted_read = shared_recording({"source", unlisted, &shared});
  CHECK(unlisted_read->observations[0].id == "c");
  CHECK(shared_recording({"source", unlisted, &shared}).get() != unlisted_read.get());
}

TEST_CASE("artifacts: the poses read are shared - other poses in the same folder are read, not mixed up") {
  TempDir temp;
  std::vector<ObservationPose> poses(2);
  poses[0].observation = "a";
  poses[1].observation = "b";
  poses[1].valid = true;
  const Artifact one = artifact_with(temp / "p", "poses.json", to_json(poses).dump(1));
  SharedReads shared;
  const auto first = shared_poses({"poses", one, &shared});
  CHECK(shared_poses({"poses", one, &shared}).get() == first.get());
  REQUIRE(first->size() == 2);
  CHECK((*first)[1].valid);

  poses[1].valid = false;  // the same folder, other bytes (a test's or a replaced entry's)
  const Artifact again = artifact_with(temp / "p", "poses.json", to_json(poses).dump(1));
  REQUIRE(shared_poses({"poses", again, &shared})->size() == 2);
  CHECK_FALSE((*shared_poses({"poses", again, &shared}))[1].valid);
}

TEST_CASE("artifacts: a process that keeps memory finds the recording its last run read - other bytes read afresh") {
  TempDir temp;
  const Artifact one = artifact_with(temp / "one", "recording.json", recording_text("a"));
  olt::test::KeepingMemory keeping(size_t{64} << 20);  // as olt watch does
  std::shared_ptr<const Recording> first;
  {
    SharedReads run;  // one run's
    first = shared_recording({"source", one, &run});
  }
  SharedReads next_run;
  CHECK(shared_recording({"source", one, &next_run}).get() == first.get());  // not parsed again

  const Artifact edited = artifact_with(temp / "one", "recording.json", recording_text("b"));  // same folder
  SharedReads after_edit;
  CHECK(shared_recording({"source", edited, &after_edit})->observations[0].id == "b");

  keep_in_memory(0);  // olt run: nothing kept between runs
  SharedReads without;
  CHECK(shared_recording({"source", one, &without}).get() != first.get());
}

TEST_CASE("artifacts: a recording's images are where its source artifact has them - its own, or referred to") {
  TempDir temp;
  Recording r;
  for (const char* id : {"a", "b", "c", "d"})
    r.observations.push_back(
        {id, "cam", 1.5, {std::string("depth/") + id + ".png", Digest(sha256_hex(id))}, std::nullopt, 0});
  r.observations[2].depth.path = (temp / "elsewhere" / "c.png").string();  // absolute: as it is
  Artifact source = artifact_with(temp / "source", "recording.json", to_json(r).dump(1));
  source.files.add("depth/b.png", Digest(sha256_hex("b")), 1, "key-other", "b.png");  // referred to
  source.files.add("depth/d.png", Digest(sha256_hex("d")), 1);                        // its own, listed
  source.files.sort();
  const auto read = shared_recording({"source", source});
  const auto& images = read->observations;
  CHECK(images[0].depth.file() == (temp / "source" / "depth/a.png").string());
  CHECK(images[0].depth.path == "depth/a.png");  // its folder shared, not in each path
  CHECK(images[1].depth.file() == (temp / "ke" / "key-other" / "b.png").string());
  CHECK(images[2].depth.file() == (temp / "elsewhere" / "c.png").string());
  REQUIRE(images[0].depth.folder);
  CHECK(*images[0].depth.folder == temp / "source");
  CHECK_FALSE(images[1].depth.folder);  // made absolute
  CHECK_FALSE(images[2].depth.folder);
  CHECK(images[3].depth.file() == (temp / "source" / "depth/d.png").string());
  CHECK(images[3].depth.folder == images[0].depth.folder);  // one folder for all
}

TEST_CASE("artifacts: an overlay's place in the labeling stage's list, and what is one") {
  CHECK(overlay_file("cam_0", "000123") == "cam_0/overlay/000123.jpg");
  CHECK(is_overlay_file(overlay_file("cam_0", "000123")));
  CHECK(is_overlay_file("kinect/overlay/1305031102.175304.jpg"));
  CHECK_FALSE(is_overlay_file("cam_0/class/000123.png"));
  CHECK_FALSE(is_overlay_file("cam_0/overlay/000123.png"));
  CHECK_FALSE(is_overlay_file("overlay/000123.jpg"));  // no sensor
  CHECK_FALSE(is_overlay_file("cam_0/frames/overlay/1.jpg"));
  CHECK_FALSE(is_overlay_file("cam_0/overlay/.jp"));
  CHECK_FALSE(is_overlay_file("labels.json"));
  // The report keeps the overlays and the stage's own files of the labeling stage's list.
  const auto looked_up = stage_kind("report").looks_up.at("propagate");
  CHECK(looked_up(ListedFile{"cam_0/overlay/1.jpg", Digest(), 1, "frame-k", "overlay.jpg"}));
  CHECK(looked_up(ListedFile{"frame_pixels.json", Digest(), 1, "", ""}));
  CHECK_FALSE(looked_up(ListedFile{"cam_0/class/1.png", Digest(), 1, "frame-k", "class.png"}));
}
