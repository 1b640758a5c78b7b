// What the system says of edits to watched files (inotify): a save is reported when its writer
// finishes it, a file still being written is not, and other files are not. Where an event must come
// the wait is long (30 s) and returns when it comes; where none must, the wait is short and nothing
// can end it early but a wrong report.
#include "olt/watch/change_events.h"

#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <thread>

#include "support/temp_dir.h"

using namespace olt;
namespace fs = std::filesystem;

namespace {

constexpr double kLong_s = 30;    // an event that must come comes long before
constexpr double kShort_s = 0.2;  // no event is to come

// False (with a warning) where this machine's inotify limits leave none: polling alone, tested by
// the daemon's tests with --poll-only.
bool listening(const ChangeEvents& events) {
  if (events.folders() > 0) return true;
  WARN("inotify is not available here (max_user_instances reached?): not tested");
  return false;
}

}  // namespace

TEST_CASE("change events: a save is finished when its writer closes or renames it, not while it writes") {
  test::TempDir dir;
  const auto file = dir / "boxes.json";
  test::write_text(file, "{}");
  const std::atomic<bool> stop{false};
  ChangeEvents events({file, dir / "gone" / "job.yaml"});  // a folder that is not there is left to polling
  if (!listening(events)) return;
  CHECK(events.folders() == 1);

  // Written and closed: finished.
  test::write_text(file, "{\"boxes\": []}");
  CHECK(events.wait(kLong_s, stop));
  CHECK(events.finished({file}));

  // Written and still open: no one woken, not finished; closed: finished.
  {
    std::ofstream open_file(file, std::ios::app);
    open_file << " " << std::flush;
    CHECK_FALSE(events.wait(kShort_s, stop));
    CHECK_FALSE(events.finished({file}));
  }
  CHECK(events.wait(kLong_s, stop));
  CHECK(events.finished({file}));

  // An editor's save: another file written, then renamed into place: finished.
  test::write_text(dir / ".boxes.json.swp", "{}");
  fs::rename(dir / ".boxes.json.swp", file);
  CHECK(events.wait(kLong_s, stop));
  CHECK(events.finished({file}));

  // Removed: not finished (a save that removes first writes after); written again: finished.
  fs::remove(file);
  CHECK_FALSE(events.wait(kShort_s, stop));
  CHECK_FALSE(events.finished({file}));
  test::write_text(file, "{}");
  CHECK(events.wait(kLong_s, stop));
  CHECK(events.finished({file}));
  // Touched (a new modification time): changed, not finished by anyone: the settle time's.
  fs::last_write_time(file, fs::last_write_time(file) + std::chrono::seconds(1));
  CHECK_FALSE(events.wait(kShort_s, stop));
  CHECK_FALSE(events.finished({file}));

  // Another file of the folder, and a watched file whose folder is not listened to: nothing said.
  test::write_text(dir / "notes.txt", "x");
  CHECK_FALSE(events.wait(kShort_s, stop));
  CHECK_FALSE(events.finished({dir / "notes.txt"}));
  CHECK_FALSE(events.finished({file, dir / "gone" / "job.yaml"}));
}

TEST_CASE("change events: a folder removed, or none listened to, leaves its files to polling") {
  test::TempDir dir;
  const std::atomic<bool> stop{false};
  CHECK(ChangeEvents({dir / "missing" / "boxes.json"}).folders() == 0);
  CHECK(ChangeEvents({dir / "boxes.json"}, /*enabled=*/false).folders() == 0);

  fs::create_directories(dir / "boxes");
  const auto file = dir / "boxes" / "boxes.json";
  ChangeEvents events({file});
  if (!listening(events)) return;
  test::write_text(file, "{}");
  CHECK(events.wait(kLong_s, stop));
  CHECK(events.finished({file}));
  // The folder gone: what the system said of its files no longer counts.
  fs::remove_all(dir / "boxes");
  events.wait(kShort_s, stop);
  CHECK_FALSE(events.finished({file}));
  CHECK(events.folders() == 0);
}

TEST_CASE("change events: a stop ends a wait under way") {
  test::TempDir dir;
  std::atomic<bool> stop{false};
  ChangeEvents events({dir / "boxes.json"});
  if (!listening(events)) return;
  const auto start = std::chrono::steady_clock::now();
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    stop = true;
  });
  CHECK_FALSE(events.wait(kLong_s, stop));
  stopper.join();
  // Well before the 30 s it was asked to wait (however busy the machine).
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(20));
}

TEST_CASE("change events: the folders with the fewest watched files are listened to, up to the limits") {
  test::TempDir dir;
  // The boxes' folder sorts last by name, and holds the fewest watched files (2; each frame's 3).
  std::vector<fs::path> files = {dir / "zz" / "boxes.json", dir / "zz" / "job.yaml"};
  for (int i = 0; i < 100; ++i)
    for (const char* name : {"depth.png", "color.png", "pose.txt"}) {
      fs::create_directories(dir / "frames" / std::to_string(i));
      files.push_back(dir / "frames" / std::to_string(i) / name);
    }
  fs::create_directories(dir / "zz");
  const std::atomic<bool> stop{false};
  ChangeEvents events(files);
  if (!listening(events)) return;
  CHECK(events.folders() == ChangeEvents::kMaxFolders);
  test::write_text(dir / "zz" / "boxes.json", "{}");
  CHECK(events.wait(kLong_s, stop));
  CHECK(events.finished({dir / "zz" / "boxes.json"}));
  // The last frame's folder by name is beyond the first 64.
  test::write_text(dir / "frames" / "99" / "depth.png", "x");
  CHECK_FALSE(events.wait(kShort_s, stop));
  CHECK_FALSE(events.finished({dir / "frames" / "99" / "depth.png"}));

  // A folder of more watched files than are listened to at all (they need not exist to be watched).
  fs::create_directories(dir / "images");
  std::vector<fs::path> images = {dir / "zz" / "boxes.json"};
  for (size_t i = 0; i <= ChangeEvents::kMaxFiles; ++i) images.push_back(dir / "images" / (std::to_string(i) + ".png"));
  ChangeEvents beside_images(images);
  CHECK(beside_images.folders() == 1);
  test::write_text(dir / "images" / "0.png", "x");
  CHECK_FALSE(beside_images.wait(kShort_s, stop));
  CHECK_FALSE(beside_images.finished({dir / "images" / "0.png"}));
}
