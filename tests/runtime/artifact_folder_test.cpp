// The stages' artifact writer: what it writes is hashed as it is written (the commit does not read it
// again), pieces and writes from many threads included; a file a library wrote through path(), a file
// written twice and a file whose write failed are hashed by the commit, from their bytes on disk.
#include "runtime/artifact_folder.h"

#include <catch2/catch.hpp>
#include <map>

#include "olt/cache/store.h"
#include "olt/core/error.h"
#include "olt/core/hash.h"
#include "olt/core/parallel.h"
#include "support/memory_file_system.h"

using namespace olt;
using namespace olt::test;

namespace {

// The digest `described` gives `path` ("" where it does not describe it).
std::string described_as(const std::deque<ArtifactFile>& described, const std::string& path) {
  for (const auto& f : described)
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

  std::deque<ArtifactFile> described = out.take_described();
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

  std::deque<ArtifactFile> described = out.take_described();
  CHECK(described_as(described, "p.txt").empty());  // not "x": the disk holds "ab"
  CHECK(described.size() == 200);
  std::vector<std::pair<std::string, std::string>> expected{{"p.txt", "ab"}};
  for (size_t i = 0; i < 200; ++i) {
    expected.emplace_back("many/" + std::to_string(i) + ".txt", std::string(i + 1, 'm'));
    CHECK(described_as(described, expected.back().first) == sha256_hex(expected.back().second));
  }
  check_files(store.commit("k1", dir, std::move(described)), expected);
}

TEST_CASE("artifact folder: bytes its previous artifact holds under the name are referred to there - others written") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  // The first run's artifact, and one it refers to (as an export's boxes file refers to its origin).
  const fs::path origin_dir = store.begin("origin");
  ArtifactFolder origin_out(origin_dir, store.files());
  origin_out.write("kept_twice.txt", "older bytes");
  const Artifact origin = store.commit("origin", origin_dir, origin_out.take_described());
  const fs::path first_dir = store.begin("first");
  ArtifactFolder first_out(first_dir, store.files());
  for (const std::string name : {"same.txt", "changed.txt", "written_twice.txt", "resized.txt"})
    first_out.write(name, "bytes of " + name);
  first_out.refer("kept_twice.txt", origin, "kept_twice.txt");
  const Artifact first = store.commit("first", first_dir, first_out.take_described());

  const fs::path dir = store.begin("second");
  ArtifactFolder out(dir, store.files(), first);
  out.write("same.txt", "bytes of same.txt");
  out.write("changed.txt", "bytes of changes.txt");        // as long, other bytes
  out.write("resized.txt", "bytes of resized.txt, more");  // other size
  out.write("written_twice.txt", "bytes of written_twice.txt");
  out.write("written_twice.txt", "bytes of written_twice.txt");  // a second write is the disk's to say
  out.write("kept_twice.txt", "older bytes");                    // referred to where its bytes are
  out.write("new.txt", "new");
  const Artifact second = store.commit("second", dir, out.take_described());

  check_files(second, {{"same.txt", "bytes of same.txt"},
                       {"changed.txt", "bytes of changes.txt"},
                       {"resized.txt", "bytes of resized.txt, more"},
                       {"written_twice.txt", "bytes of written_twice.txt"},
                       {"kept_twice.txt", "older bytes"},
                       {"new.txt", "new"}});
  CHECK(second.file("same.txt")->in == "first");
  CHECK(second.file("same.txt")->as == "same.txt");
  CHECK(second.file("kept_twice.txt")->in == "origin");
  const std::map<std::string, std::string> own{{"changed.txt", "bytes of changes.txt"},
                                               {"resized.txt", "bytes of resized.txt, more"},
                                               {"written_twice.txt", "bytes of written_twice.txt"},
                                               {"new.txt", "new"}};
  for (const auto& [file, bytes] : own) {
    INFO(file);
    CHECK(second.file(file)->in.empty());
    CHECK(second.path(file) == second.dir / file);
    CHECK(store.files().read(second.path(file)) == bytes);
  }
  CHECK(store.files().read(second.path("same.txt")) == "bytes of same.txt");
  CHECK(store.files().read(second.path("kept_twice.txt")) == "older bytes");
  CHECK(store.verify().problems.empty());
}
