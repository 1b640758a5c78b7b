// The stages' artifact writer: what it writes is hashed as it is written (the commit does not read it
// again), pieces included; a file a library wrote through path() is hashed by the commit, from its
// bytes on disk, whatever was written there before.
#include "runtime/artifact_folder.h"

#include <catch2/catch.hpp>

#include "olt/cache/store.h"
#include "olt/core/hash.h"
#include "support/memory_file_system.h"

using namespace olt;
using namespace olt::test;

TEST_CASE(
    "artifact folder: files are described with the digest of the bytes written - library files left to the commit") {
  Place place(GENERATE(true, false));
  const Store store(place.root(), place.files());
  const fs::path dir = store.begin("k1");
  ArtifactFolder out(dir, store.files());
  out.write("one.txt", "one");
  out.write("twice.txt", "first");
  out.write("twice.txt", "second");  // the last write counts
  out.write_pieces("pieces.txt", [](const PieceSink& sink) {
    sink("ab");
    sink("cd");
  });
  out.write("library.txt", "written before the library");
  store.files().write(out.path("library.txt"), "the library's");
  store.files().write(out.path("only_library.txt"), "lib");

  std::deque<ArtifactFile> described = out.take_described();
  const auto described_as = [&](const std::string& path) {
    std::string sha;
    for (const auto& f : described)
      if (f.path == path) sha = f.sha256;  // the last
    return sha;
  };
  CHECK(described_as("one.txt") == sha256_hex("one"));
  CHECK(described_as("twice.txt") == sha256_hex("second"));
  CHECK(described_as("pieces.txt") == sha256_hex("abcd"));
  CHECK(described_as("library.txt").empty());
  CHECK(described_as("only_library.txt").empty());

  const Artifact a = store.commit("k1", dir, std::move(described));
  REQUIRE(a.files.size() == 5);
  for (const auto& [path, bytes] : std::vector<std::pair<std::string, std::string>>{{"library.txt", "the library's"},
                                                                                    {"one.txt", "one"},
                                                                                    {"only_library.txt", "lib"},
                                                                                    {"pieces.txt", "abcd"},
                                                                                    {"twice.txt", "second"}}) {
    REQUIRE(a.file(path));
    CHECK(a.file(path)->sha256 == sha256_hex(bytes));
    CHECK(a.file(path)->size == bytes.size());
  }
  CHECK(store.verify().problems.empty());
}
