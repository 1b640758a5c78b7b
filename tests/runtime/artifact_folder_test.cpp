// The stages' artifact writer: what it writes is hashed as it is written (the commit does not read it
// again), pieces and writes from many threads included; a file a library wrote through path(), a file
// written twice and a file whose write failed are hashed by the commit, from their bytes on disk.
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
