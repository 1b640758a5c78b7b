// The FileSystem operations the cache and publishing rely on, on the real file system and on the
// memory one the runtime's tests use: both must answer alike, or the memory tests prove nothing.
#include "olt/core/file_system.h"

#include <fcntl.h>
#include <linux/fiemap.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <functional>
#include <future>
#include <thread>
#include <vector>

#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "support/memory_file_system.h"

using namespace olt;
using namespace olt::test;

TEST_CASE("file system: write, read, append, list and stat - a missing file is an InputError naming it") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root();
  files.write(root / "a/b/c.txt", "abc");  // parent folders created
  files.append(root / "a/log", "1\n");
  files.append(root / "a/log", "2\n");
  CHECK(files.read(root / "a/b/c.txt") == "abc");
  CHECK(files.read(root / "a/log") == "1\n2\n");
  CHECK(files.list(root / "a") == std::vector<std::string>{"b", "log"});
  CHECK(files.list(root / "nothing").empty());
  CHECK(files.stat(root / "a/b/c.txt").is_file());
  CHECK(files.stat(root / "a/b/c.txt").size == 3);
  CHECK(files.stat(root / "a/b").is_folder());
  CHECK_FALSE(files.stat(root / "a/x").exists());
  CHECK(files.files_below(root / "a") == std::vector<std::string>{"b/c.txt", "log"});
  CHECK(files.sha256(root / "a/b/c.txt") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  try {
    files.read(root / "a/missing.txt");
    FAIL("no such file");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("missing.txt") && Catch::Contains("file not found"));
  }
  CHECK_THROWS_AS(files.read(root / "a/b"), InputError);
}

TEST_CASE("file system: a text written in pieces is their concatenation - none is an empty file") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root();
  files.write(root / "t.txt", "old bytes, longer than the new ones");
  write_pieces(files, root / "t.txt", [](const PieceSink& sink) {
    sink("ab");
    sink("");
    sink("cd");
  });
  CHECK(files.read(root / "t.txt") == "abcd");
  write_pieces(files, root / "t.txt", [](const PieceSink&) {});
  CHECK(files.read(root / "t.txt").empty());
  // Pieces hands its text on once it passes a megabyte, and the rest when flushed.
  std::vector<size_t> sizes;
  std::string joined;
  const PieceSink sink = [&](std::string_view piece) {
    sizes.push_back(piece.size());
    joined += piece;
  };
  Pieces pieces(sink);
  for (int i = 0; i < 3000; ++i) {
    pieces.text() += std::string(1000, static_cast<char>('a' + i % 26));
    pieces.next();
  }
  CHECK(sizes.size() == 2);  // 1,049,000 bytes, then 1,049,000 more; the rest waits for flush
  pieces.flush();
  CHECK(sizes.size() == 3);
  CHECK(joined.size() == 3000000);
  CHECK(joined.substr(1000 * 25, 3) == "zzz");
}

TEST_CASE("file system: hard links share their bytes - a copy does not - rename replaces files, not full folders") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root();
  files.write(root / "one", "1");
  files.link(root / "one", root / "linked/one");
  files.copy(root / "one", root / "copied");
  CHECK(files.stat(root / "linked/one").identity == files.stat(root / "one").identity);
  files.write(root / "one", "changed");  // in place: every hard link sees it, the copy does not
  CHECK(files.read(root / "linked/one") == "changed");
  CHECK(files.read(root / "copied") == "1");

  CHECK(files.rename(root / "copied", root / "one"));
  CHECK(files.read(root / "one") == "1");
  CHECK_FALSE(files.stat(root / "copied").exists());
  files.write(root / "full/x", "x");
  files.write(root / "moving/y", "y");
  CHECK_FALSE(files.rename(root / "moving", root / "full"));
  CHECK(files.read(root / "moving/y") == "y");
  CHECK(files.rename(root / "moving", root / "moved"));
  CHECK(files.read(root / "moved/y") == "y");
  files.write_atomic(root / "moved/y", "new");
  CHECK(files.read(root / "moved/y") == "new");
  CHECK(files.list(root / "moved") == std::vector<std::string>{"y"});  // no temporary left
}

TEST_CASE("file system: a copy hashed gives the digest of the bytes copied - folders made, a longer file cut") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root();
  std::string big(200000, 'a');  // across several reads
  for (size_t i = 0; i < big.size(); i += 7) big[i] = static_cast<char>('0' + i % 10);
  files.write(root / "big", big);
  CHECK(files.copy_hashed(root / "big", root / "new/folders/big").sha256 == sha256_hex(big));
  CHECK(files.read(root / "new/folders/big") == big);
  files.write(root / "small", "small");
  CHECK(files.copy_hashed(root / "small", root / "new/folders/big").sha256 == sha256_hex("small"));  // replaced whole
  CHECK(files.read(root / "new/folders/big") == "small");
  files.copy(root / "small", root / "plain/copy");  // a plain copy makes its folders too
  CHECK(files.read(root / "plain/copy") == "small");
  // A missing source is the run's failure (a cache file gone), not invalid input: FileSystemError.
  CHECK_THROWS_WITH(files.copy_hashed(root / "missing", root / "to"), Catch::Contains("missing"));
  CHECK_THROWS_AS(files.copy_hashed(root / "missing", root / "to"), FileSystemError);
  CHECK_THROWS_AS(files.copy(root / "missing", root / "to"), FileSystemError);
  files.write(root / "in_the_way", "a file");
  CHECK_THROWS_AS(files.copy_hashed(root / "small", root / "in_the_way/x"), FileSystemError);
  if (place.real()) {
    // A named pipe on either side is refused, not waited on.
    REQUIRE(::mkfifo((root / "pipe").c_str(), 0644) == 0);
    CHECK_THROWS_AS(files.copy_hashed(root / "pipe", root / "from_pipe"), FileSystemError);
    CHECK_THROWS_AS(files.copy_hashed(root / "small", root / "pipe"), FileSystemError);
    // A copy onto the file itself (a hard link to it) is refused, and leaves its bytes.
    files.link(root / "small", root / "same");
    CHECK_THROWS_WITH(files.copy_hashed(root / "small", root / "same"), Catch::Contains("same file"));
    CHECK(files.read(root / "small") == "small");
  }
}

namespace {

// Whether every extent of `file` is shared with another file (FIEMAP): what a clone's are, and a
// copy's are not. False for a file with no extents (nothing written to the disk yet: synced first).
bool blocks_shared(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  REQUIRE(fd >= 0);
  REQUIRE(::fsync(fd) == 0);
  constexpr uint32_t kExtents = 32;
  // The request and the extents after it, in 8-byte words (the structures' alignment).
  std::vector<uint64_t> words((sizeof(fiemap) + kExtents * sizeof(fiemap_extent)) / sizeof(uint64_t) + 1, 0);
  auto* map = reinterpret_cast<fiemap*>(words.data());  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  map->fm_length = FIEMAP_MAX_OFFSET;
  map->fm_flags = FIEMAP_FLAG_SYNC;
  map->fm_extent_count = kExtents;
  const int result = ::ioctl(fd, FS_IOC_FIEMAP, map);
  ::close(fd);
  REQUIRE(result == 0);
  if (map->fm_mapped_extents == 0) return false;
  for (uint32_t i = 0; i < map->fm_mapped_extents; ++i)
    if (!(map->fm_extents[i].fe_flags & FIEMAP_EXTENT_SHARED)) return false;
  return true;
}

// Writes `bytes` into `file` at `offset`, in place: no truncation, the rest of the file kept.
void write_in_place(const fs::path& file, off_t offset, std::string_view bytes) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CLOEXEC);
  REQUIRE(fd >= 0);
  const ssize_t written = ::pwrite(fd, bytes.data(), bytes.size(), offset);
  ::close(fd);
  REQUIRE(written == static_cast<ssize_t>(bytes.size()));
}

// A folder removed with everything in it when it goes, the test passed or not.
struct RemovedAfter {
  fs::path folder;
  ~RemovedAfter() { real_file_system().remove(folder); }
};

}  // namespace

// Needs a folder on a file system that clones (XFS with reflink, Btrfs) named by OLT_TEST_CLONING_DIR:
// `.ci/run` mounts one where the machine lets it; ctest reports the test skipped where it is not set.
// Elsewhere the copy is tested above.
TEST_CASE("file system: where the file system clones, a copy hashed is a clone - no block written twice") {
  const char* dir = std::getenv("OLT_TEST_CLONING_DIR");
  if (!dir || !*dir) {
    WARN("OLT_TEST_CLONING_DIR is not set: publishing's clones are not tested here (a folder on XFS or Btrfs)");
    return;
  }
  const RemovedAfter root{fs::path(dir) / ("olt-clone-test-" + std::to_string(::getpid()))};
  FileSystem& files = real_file_system();
  std::string bytes(256 * 1024, 'b');  // whole blocks: a clone over a longer file would keep its rest
  for (size_t i = 0; i < bytes.size(); i += 5) bytes[i] = static_cast<char>('a' + i % 26);
  files.write(root.folder / "cache/entry", bytes);
  files.write(root.folder / "out/label", std::string(400000, 'o'));  // an older, longer file in the way
  const FileSystem::Copied copied = files.copy_hashed(root.folder / "cache/entry", root.folder / "out/label");
  CHECK(copied.sha256 == sha256_hex(bytes));
  CHECK(copied.cloned);
  CHECK(files.read(root.folder / "out/label") == bytes);
  CHECK(blocks_shared(root.folder / "out/label"));
  CHECK(blocks_shared(root.folder / "cache/entry"));
  // The clone is a file of its own: written to in place, it parts from the source, which keeps its bytes.
  write_in_place(root.folder / "out/label", 70000, "edited by hand");
  CHECK(files.read(root.folder / "cache/entry") == bytes);
  CHECK(files.read(root.folder / "out/label").substr(70000, 14) == "edited by hand");
  CHECK(files.copy_hashed(root.folder / "cache/entry", root.folder / "out/label").sha256 == sha256_hex(bytes));
  CHECK(files.read(root.folder / "out/label") == bytes);
  // Into the temporary folder (across file systems where it is not on this one: copied) the same bytes.
  TempDir elsewhere;
  CHECK(files.copy_hashed(root.folder / "cache/entry", elsewhere / "label").sha256 == sha256_hex(bytes));
  CHECK(files.read(elsewhere / "label") == bytes);
}

TEST_CASE("file system: stat and remove never follow a symbolic link - list and read do") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root();
  files.write(root / "elsewhere/keep.txt", "keep");
  place.symlink(root / "elsewhere", root / "out/link");
  CHECK(files.stat(root / "out/link").type == FileStat::Type::link);
  CHECK(files.stat(root / "out/link", true).is_folder());
  CHECK(files.list(root / "out/link") == std::vector<std::string>{"keep.txt"});
  CHECK(files.read(root / "out/link/keep.txt") == "keep");
  CHECK(files.files_below(root / "out").empty());  // links are not walked
  files.remove(root / "out");
  CHECK_FALSE(files.stat(root / "out").exists());
  CHECK(files.read(root / "elsewhere/keep.txt") == "keep");
}

TEST_CASE("file system: temporaries of dead processes are removed, a live process's and another machine's stay") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root();
  const std::string here = host_name(), alive = std::to_string(::getpid());
  // No process has pid 999999999 (above pid_max).
  files.write(root / "out" / (".tmp.a.png." + here + ".999999999.0"), "dead");
  files.write(root / "out/sub" / (".tmp.b.png." + here + ".999999999.3") / "x", "dead folder");
  files.write(root / "out" / (".tmp.c.png." + here + "." + alive + ".1"), "alive");
  files.write(root / "out/.tmp.d.png.other-machine.999999999.0", "another machine's: its pid means nothing here");
  files.write(root / "out/a.png", "kept");
  files.write(root / "elsewhere" / (".tmp.e.png." + here + ".999999999.0"), "not below the output");
  place.symlink(root / "elsewhere", root / "out/link");
  CHECK(remove_orphaned_temps(files, root / "out") == 2);
  CHECK(files.files_below(root / "out") == std::vector<std::string>{".tmp.c.png." + here + "." + alive + ".1",
                                                                    ".tmp.d.png.other-machine.999999999.0", "a.png"});
  CHECK(files.stat(root / "elsewhere" / (".tmp.e.png." + here + ".999999999.0")).is_file());
  CHECK(temp_sibling("/x/a.png").filename().string().rfind(".tmp.a.png." + here + "." + alive + ".", 0) == 0);
}

TEST_CASE("memory file system: a full disk fails the write that does not fit, with the system's words") {
  MemoryFileSystem files;
  files.write("/a", "1");
  files.fail_writes_after(1);
  files.write("/b", "2");
  try {
    files.write("/c", "3");
    FAIL("the disk is full");
  } catch (const FileSystemError& e) {
    CHECK(std::string(e.what()) == "/c: write failed: No space left on device");
  }
  CHECK_THROWS_AS(files.link("/a", "/d"), FileSystemError);
  CHECK(files.writes() == 2);
  CHECK_FALSE(files.stat("/c").exists());
}

TEST_CASE("file system: a file read as a stream gives its bytes across buffers - a missing one names it") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  std::string bytes;
  for (int i = 0; i < 30000; ++i) bytes += std::to_string(i * 7919) + (i % 13 ? "," : "\n");  // ~170 KB
  files.write(place.root() / "big.txt", bytes);
  const auto stream = files.read_stream(place.root() / "big.txt");
  const std::string back((std::istreambuf_iterator<char>(*stream)), std::istreambuf_iterator<char>());
  CHECK(back == bytes);
  try {
    files.read_stream(place.root() / "missing.txt");
    FAIL("opened a missing file");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("missing.txt") != std::string::npos);
  }
  files.make_folders(place.root() / "folder");
  CHECK_THROWS_AS(files.read_stream(place.root() / "folder"), InputError);
}

TEST_CASE("file system: a path stays inside its folder unless it is absolute or has a . or .. part") {
  for (const std::string inside : {"a", "a/b.png", "a//b", "a/", "..a/b", "a/..b", "a/b.", ".hidden/x"})
    CHECK(olt::stays_inside(inside));
  for (const std::string outside : {"", "/a", "//a", "..", ".", "../a", "a/../b", "a/..", "./a", "a/./b", "a/."})
    CHECK_FALSE(olt::stays_inside(outside));
}

TEST_CASE("file system: a file is the same file until it is replaced - a rename into place is another file") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path file = place.root() / "meta.json";
  files.write(file, "one");
  const FileStat first = files.stat(file);
  CHECK(first.same_file(files.stat(file)));
  files.write_atomic(file, "two");  // written beside it and renamed into place, as the cache writes
  const FileStat second = files.stat(file);
  CHECK(!first.same_file(second));
  CHECK(second.same_file(files.stat(file)));
  files.remove(file);
  CHECK(!second.same_file(files.stat(file)));
  CHECK(!FileStat{}.same_file(FileStat{}));  // nothing is not a file
}

TEST_CASE("file system: a folder watch sees what is made, written, removed or moved in its folders - not reads") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root();
  files.write(root / "out/a/one.png", "1");
  files.write(root / "out/b/two.png", "2");
  files.make_folders(root / "other");
  const std::vector<fs::path> folders = {root / "out", root / "out/a", root / "out/b"};
  // Each change in turn, to a watch begun just before it: one that nothing changed since stays unchanged.
  const std::vector<std::pair<std::string, std::function<void()>>> changes = {
      {"a file written in place", [&] { files.write(root / "out/a/one.png", "11"); }},
      {"a file made", [&] { files.write(root / "out/b/three.png", "3"); }},
      {"a file removed", [&] { files.remove(root / "out/b/three.png"); }},
      {"a file moved in",
       [&] {
         files.write(root / "other/x", "x");
         files.rename(root / "other/x", root / "out/x");
       }},
      {"a watched folder moved away", [&] { files.rename(root / "out/b", root / "other/b"); }},
  };
  for (const auto& [what, change] : changes) {
    INFO(what);
    const std::unique_ptr<FolderWatch> watch = files.watch(folders);
    REQUIRE(watch);
    files.read(root / "out/a/one.png");  // reading and looking change nothing
    files.stat(root / "out/a/one.png");
    files.write(root / "other/y", "y");  // nor does a change in a folder not watched
    CHECK_FALSE(watch->changed());
    change();
    CHECK(watch->changed());
    CHECK(watch->changed());  // it stays so
  }
  CHECK(files.watch({root / "out/b"}) == nullptr);  // moved away: nothing to watch there
}

TEST_CASE("file system: a folder watch begun again forgets what changed before - not once a folder of its own moved") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path root = place.root();
  files.write(root / "out/a/one.png", "1");
  files.make_folders(root / "other");
  const std::unique_ptr<FolderWatch> watch = files.watch({root / "out", root / "out/a"});
  REQUIRE(watch);
  // A publish's own changes, a new folder among them: forgotten, and the new folder watched too.
  files.write(root / "out/a/one.png", "11");
  files.write(root / "out/c/two.png", "2");
  CHECK(watch->changed());
  REQUIRE(watch->restart({root / "out", root / "out/a", root / "out/c"}));
  CHECK_FALSE(watch->changed());
  files.write(root / "other/y", "y");  // not watched
  CHECK_FALSE(watch->changed());
  files.write(root / "out/c/two.png", "22");  // in the folder it watches since it began again
  CHECK(watch->changed());
  REQUIRE(watch->restart({root / "out", root / "out/a", root / "out/c"}));
  files.remove(root / "out/a/one.png");
  CHECK(watch->changed());
  REQUIRE(watch->restart({root / "out", root / "out/a", root / "out/c"}));
  CHECK_FALSE(watch->changed());
  // A folder it watches moved away (and one made in its place): it no longer watches that path, and
  // says so rather than begin again.
  files.rename(root / "out/a", root / "other/a");
  files.write(root / "out/a/one.png", "1");
  CHECK(watch->changed());
  CHECK_FALSE(watch->restart({root / "out", root / "out/a", root / "out/c"}));
  // Nor over a folder that is not there.
  const std::unique_ptr<FolderWatch> again = files.watch({root / "out"});
  REQUIRE(again);
  CHECK_FALSE(again->restart({root / "out", root / "missing"}));
}

TEST_CASE("file system: a lock waited for is taken once its holder lets go, or not at all once asked to stop") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path lock_file = place.root() / "locks" / "stage-ab.lock";
  std::atomic<bool> stop{false};
  struct Waited {  // whether it took the lock, and how often it said it waits
    bool took = false;
    int waits = 0;
  };
  // `files.lock` on a thread of its own (which releases what it took), `once_waiting` called once it
  // says it waits. Should the wait not end in 60 s, the holder lets go and the stop is set, so that a
  // broken wait fails the test rather than hang it.
  const auto wait_on_thread = [&](std::unique_ptr<FileSystem::Lock>& holder,
                                  const std::function<void()>& once_waiting) {
    Waited waited;
    std::promise<void> waiting, done;
    std::future<void> said = waiting.get_future(), ended = done.get_future();
    std::thread waiter([&] {
      const auto lock = files.lock(
          lock_file, false,
          [&] {
            if (++waited.waits == 1) waiting.set_value();
          },
          &stop);
      waited.took = lock != nullptr;
      done.set_value();
    });
    if (said.wait_for(std::chrono::seconds(60)) == std::future_status::ready) once_waiting();
    if (ended.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
      holder.reset();
      stop = true;
      FAIL_CHECK("the wait did not end");
    }
    waiter.join();
    return waited;
  };
  {
    auto holder = files.lock(lock_file, false, nullptr, nullptr);
    const Waited waited = wait_on_thread(holder, [&] { holder.reset(); });  // the holder lets go
    CHECK(waited.took);
    CHECK(waited.waits == 1);
  }
  {
    auto holder = files.lock(lock_file, false, nullptr, nullptr);
    const Waited waited = wait_on_thread(holder, [&] { stop = true; });
    CHECK_FALSE(waited.took);
    CHECK(waited.waits == 1);
  }
  CHECK(files.try_lock(lock_file, false) != nullptr);  // nothing left held by the wait that stopped
  // Shared with a shared holder: taken at once, even once asked to stop (on a thread of its own: a
  // thread must not take a lock it holds).
  const auto holder = files.lock(lock_file, true, nullptr, nullptr);
  int waits = 0;
  const bool took = std::async(std::launch::async, [&] {
                      return files.lock(
                                 lock_file, true, [&] { ++waits; }, &stop) != nullptr;
                    }).get();
  CHECK(took);
  CHECK(waits == 0);
}

TEST_CASE("file system: a lock another holder has is not taken without waiting - a free one is") {
  Place place(GENERATE(true, false));
  FileSystem& files = place.files();
  const fs::path lock_file = place.root() / "locks" / "gc.lock";
  {
    const auto shared = files.lock(lock_file, true, nullptr, nullptr);
    CHECK(files.try_lock(lock_file, true) != nullptr);  // shared with shared
    CHECK(files.try_lock(lock_file, false) == nullptr);
  }
  const auto exclusive = files.try_lock(lock_file, false);
  CHECK(exclusive != nullptr);
}
