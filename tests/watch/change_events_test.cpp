// What the system says of edits to watched files (inotify): each kind of save is reported, finished
// or not, and edits to other files in the same folder are not. Every wait is long (30 s) where an
// event must come, so the test does not depend on how soon it comes: it returns when it does.
#include "olt/watch/change_events.h"

#include <catch2/catch.hpp>
#include <fstream>

#include "support/temp_dir.h"

using namespace olt;

namespace {

constexpr double kLong_s = 30;  // an event that must come comes long before

}  // namespace

TEST_CASE("change events: saves of a watched file are reported, finished or not, and other files are not") {
  test::TempDir dir;
  const auto file = dir / "boxes.json";
  test::write_text(file, "{}");
  const std::atomic<bool> stop{false};
  ChangeEvents events({file, dir / "gone" / "job.yaml"});  // a folder that is not there is left to polling
  if (!events.active()) {  // inotify's limits reached on this machine: polling alone, tested elsewhere
    WARN("inotify is not available here (max_user_instances reached?): not tested");
    return;
  }

  // Written and closed: finished.
  test::write_text(file, "{\"boxes\": []}");
  CHECK(events.wait(kLong_s, stop) == ChangeEvent::finished);

  // Written and still open: changed; then closed: finished.
  {
    std::ofstream open_file(file, std::ios::app);
    open_file << " " << std::flush;
    CHECK(events.wait(kLong_s, stop) == ChangeEvent::changed);
  }
  CHECK(events.wait(kLong_s, stop) == ChangeEvent::finished);

  // An editor's save: another file written, then renamed into place. The other file's events are
  // left out, the rename is a finished change.
  test::write_text(dir / ".boxes.json.swp", "{}");
  std::filesystem::rename(dir / ".boxes.json.swp", file);
  CHECK(events.wait(kLong_s, stop) == ChangeEvent::finished);

  // Removed: changed (a save that removes first and writes after is not finished yet).
  std::filesystem::remove(file);
  CHECK(events.wait(kLong_s, stop) == ChangeEvent::changed);

  // Another file of the folder: nothing (waited for briefly: nothing is to come).
  test::write_text(dir / "notes.txt", "x");
  CHECK(events.wait(0.2, stop) == ChangeEvent::none);
}

TEST_CASE("change events: none where no watched folder exists, and a stop ends a wait") {
  test::TempDir dir;
  const std::atomic<bool> stop{false}, stopped{true};
  ChangeEvents nowhere({dir / "missing" / "boxes.json"});
  CHECK_FALSE(nowhere.active());
  CHECK(nowhere.wait(0.05, stop) == ChangeEvent::none);

  ChangeEvents events({dir / "boxes.json"});
  if (!events.active()) {
    WARN("inotify is not available here (max_user_instances reached?): not tested");
    return;
  }
  test::write_text(dir / "boxes.json", "{}");
  // Stopped: returns at once with nothing, the event left for a wait that is not stopped.
  CHECK(events.wait(kLong_s, stopped) == ChangeEvent::none);
  CHECK(events.wait(kLong_s, stop) == ChangeEvent::finished);
}

TEST_CASE("change events: a recording with a folder per frame leaves its images to polling") {
  test::TempDir dir;
  std::vector<std::filesystem::path> files = {dir / "boxes.json", dir / "job.yaml"};
  for (int i = 0; i < 100; ++i) {
    std::filesystem::create_directories(dir / "frames" / std::to_string(i));
    files.push_back(dir / "frames" / std::to_string(i) / "depth.png");
    files.push_back(dir / "frames" / std::to_string(i) / "color.png");
  }
  const std::atomic<bool> stop{false};
  ChangeEvents events(files);
  if (!events.active()) {
    WARN("inotify is not available here (max_user_instances reached?): not tested");
    return;
  }
  CHECK(events.folders() == ChangeEvents::kMaxFolders);
  // The boxes' folder (two watched files) among them, before the frames' (two each, later by name).
  test::write_text(dir / "boxes.json", "{}");
  CHECK(events.wait(kLong_s, stop) == ChangeEvent::finished);
  // The last frame's folder by name is beyond the first 64: its image is polling's (nothing said).
  test::write_text(dir / "frames" / "99" / "depth.png", "x");
  CHECK(events.wait(0.2, stop) == ChangeEvent::none);
}
