// The stages' artifact writer: what it writes is hashed as it is written (the commit does not read it
// again), pieces and writes from many threads included; a file a library wrote through path(), a file
// written twice and a file whose write failed are hashed by the commit, from their bytes on disk. A
// file written with the bytes the stage's last run wrote under its name is referred to there (`olt
// watch`), where those bytes first were.
#include "runtime/artifact_folder.h"

#include <catch2/catch.hpp>

#include "olt/cache/store.h"
#include "olt/core/error.h"
#include "olt/core/hash.h"
#include "olt/core/parallel.h"
#include "support/memory_file_system.h"

using namespace olt;
using namespace olt::test;

namespace {

// The digest `described` gives `path` ("" where it does not describe it).
std::string described_as(const ArtifactFiles& described, const std::string& path) {
  for (const ListedFile f : described)
    if (f.path == path) return f.sha256.hex();
  return "";
}

// Every file of `a` listed with the digest and size of `bytes`.
void check_files(const Artifact& a, const std::vector<std::pair<std::string, std::string>>& files) {
  REQUIRE(a.files.size() == files.size());
  for (const auto& [path, bytes] : files) {
    REQUIRE(a.file(path));
    CHECK(a.file(path)->sha256 == sha256_hex(bytes));
    CHECK(a.file(path)->size == bytes.size());
  }
}

}  // namespace

TEST_CASE("artifact folder: files are described with the digest of the bytes written - others left to the commit") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  const fs::path dir = store.begin("k1");
  ArtifactFolder out(dir, store.files());
  out.write("one.txt", "one");
  out.write("sub//two.txt", "two");  // listed as the store lists it
  out.write("twice.txt", "first");
  out.write("twice.txt", "second");
  out.write_pieces("pieces.txt", [](const PieceSink& sink) {
    sink("ab");
    sink("cd");
  });
  out.write("library.txt", "written before the library");
  store.files().write(out.path("library.txt"), "the library's");
  store.files().write(out.path("only_library.txt"), "lib");

  ArtifactFiles described = out.take_described();
  CHECK(described_as(described, "one.txt") == sha256_hex("one"));
  CHECK(described_as(described, "sub/two.txt") == sha256_hex("two"));
  CHECK(described_as(described, "pieces.txt") == sha256_hex("abcd"));
  CHECK(described_as(described, "twice.txt").empty());  // which write came last is the disk's to say
  CHECK(described_as(described, "library.txt").empty());
  CHECK(described_as(described, "only_library.txt").empty());

  const Artifact a = store.commit("k1", dir, std::move(described));
  check_files(a, {{"library.txt", "the library's"},
                  {"one.txt", "one"},
                  {"only_library.txt", "lib"},
                  {"pieces.txt", "abcd"},
                  {"sub/two.txt", "two"},
                  {"twice.txt", "second"}});
  CHECK(store.verify().problems.empty());
}

TEST_CASE(
    "artifact folder: a write that failed leaves its file to the commit - writes from many threads all described") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const fs::path dir = store.begin("k1");
  ArtifactFolder out(dir, files);
  out.write("p.txt", "x");
  files.fail_writes_after(1);  // the first piece is written, the second fails
  CHECK_THROWS_AS(out.write_pieces("p.txt",
                                   [](const PieceSink& sink) {
                                     sink("ab");
                                     sink("cd");
                                   }),
                  FileSystemError);
  files.fail_writes_after(-1);
  parallel_for(200, [&](size_t i) { out.write("many/" + std::to_string(i) + ".txt", std::string(i + 1, 'm')); });

  ArtifactFiles described = out.take_described();
  CHECK(described_as(described, "p.txt").empty());  // not "x": the disk holds "ab"
  CHECK(described.size() == 200);
  std::vector<std::pair<std::string, std::string>> expected{{"p.txt", "ab"}};
  for (size_t i = 0; i < 200; ++i) {
    expected.emplace_back("many/" + std::to_string(i) + ".txt", std::string(i + 1, 'm'));
    CHECK(described_as(described, expected.back().first) == sha256_hex(expected.back().second));
  }
  check_files(store.commit("k1", dir, std::move(described)), expected);
}

TEST_CASE("artifact folder: files referred to and files written are described together, keys and names kept") {
  MemoryFileSystem files;
  const Store store("/cache", files);
  const fs::path from_dir = store.begin("frame-1");
  files.write(from_dir / "class.png", "c");
  files.write(from_dir / "masks.json", "m");
  const Artifact frame = store.commit("frame-1", from_dir);
  for (const int written : {1, 5}) {  // fewer files written than referred to, then more
    CAPTURE(written);
    const fs::path dir = store.begin("k" + std::to_string(written));
    ArtifactFolder out(dir, files);
    out.refer("cam/class/1.png", frame, "class.png");
    out.refer("cam/masks/1.json", frame, "masks.json");
    out.refer("cam/class/1-again.png", frame, "class.png");
    for (int i = 0; i < written; ++i) out.write("own/" + std::to_string(i) + ".txt", std::to_string(i));
    const ArtifactFiles described = out.take_described();
    REQUIRE(described.size() == static_cast<size_t>(3 + written));
    const Artifact a = store.commit("k" + std::to_string(written), dir, described);
    const auto referred = a.file("cam/masks/1.json");
    REQUIRE(referred);
    CHECK(referred->in == "frame-1");
    CHECK(referred->as == "masks.json");
    CHECK(referred->sha256 == sha256_hex("m"));
    CHECK(a.file("cam/class/1.png")->in.data() == a.file("cam/class/1-again.png")->in.data());  // one key
    CHECK(a.file("own/0.txt")->in.empty());
    CHECK(a.file("own/0.txt")->sha256 == sha256_hex("0"));
    CHECK(files.read(a.path("cam/class/1-again.png")) == "c");
  }
  CHECK(store.verify().problems.empty());
}

TEST_CASE("artifact folder: a file with the bytes the last run wrote is referred to where they are, not written") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  FileSystem& files = store.files();
  // A run of the stage (nothing before it: it only starts the record), then more, each given what the
  // one before wrote (`carry`; without, a plain run) and writing what `write` does.
  ArtifactFiles before;
  const auto run = [&](const std::string& key, bool carry, const std::function<void(ArtifactFolder&)>& write) {
    const fs::path dir = store.begin(key);
    ArtifactFolder out(dir, files);
    if (carry) out.carry_from(before);
    write(out);
    const Artifact a = store.commit(key, dir, out.take_described());
    if (carry) before = out.carried_forward(a);
    return a;
  };
  const auto pieces = [](ArtifactFolder& out, const std::string& file, const std::string& bytes) {
    out.write_pieces(file, [&](const PieceSink& sink) { sink(bytes); });
  };
  const Artifact first = run("k1", true, [&](ArtifactFolder& out) {
    out.write("same.txt", "same");
    out.write("changed.txt", "one");
    out.write("sub//twice.txt", "x");
    pieces(out, "pieces.txt", "pp");
  });
  CHECK(before.size() == 4);
  CHECK(first.file("same.txt")->in.empty());

  const Artifact second = run("k2", true, [&](ArtifactFolder& out) {
    out.write("same.txt", "same");    // carried: referred to in k1
    out.write("changed.txt", "two");  // written
    out.write("sub/twice.txt", "x");  // carried, then written again: which bytes came last is the disk's
    out.write("sub/twice.txt", "y");
    pieces(out, "pieces.txt", "pp");  // pieces are written: their bytes are known once written
    out.write("new.txt", "new");
  });
  check_files(
      second,
      {{"changed.txt", "two"}, {"new.txt", "new"}, {"pieces.txt", "pp"}, {"same.txt", "same"}, {"sub/twice.txt", "y"}});
  CHECK(second.file("same.txt")->in == "k1");
  CHECK(second.file("same.txt")->as == "same.txt");
  CHECK_FALSE(files.stat(second.dir / "same.txt").exists());  // not written again
  CHECK(files.read(second.path("same.txt")) == "same");
  CHECK(second.file("changed.txt")->in.empty());
  CHECK(second.file("sub/twice.txt")->in.empty());
  CHECK(files.read(second.path("sub/twice.txt")) == "y");
  CHECK(second.file("pieces.txt")->in.empty());

  // The third run finds each file's bytes where they first were, not in the run before that referred
  // to them; a file it does not write is not listed.
  const Artifact third = run("k3", true, [&](ArtifactFolder& out) {
    out.write("same.txt", "same");
    out.write("changed.txt", "two");
    out.write("sub/twice.txt", "z");
  });
  check_files(third, {{"changed.txt", "two"}, {"same.txt", "same"}, {"sub/twice.txt", "z"}});
  CHECK(third.file("same.txt")->in == "k1");
  CHECK(third.file("changed.txt")->in == "k2");
  CHECK(third.file("sub/twice.txt")->in.empty());
  CHECK(store.verify().problems.empty());

  // What the last run refers to is kept by the garbage collector with it; the rest goes.
  store.mark();
  CHECK(store.collect_garbage({"k3"}).removed == 0);
  const Artifact unrelated = run("k4", false, [&](ArtifactFolder& out) { out.write("same.txt", "same"); });
  CHECK(unrelated.file("same.txt")->in.empty());  // not carrying: written
  CHECK(store.collect_garbage({"k3"}).removed == 1);
  CHECK(files.read(store.find("k3")->path("same.txt")) == "same");
  CHECK(store.verify().problems.empty());
}
