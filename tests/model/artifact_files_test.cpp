// An artifact's file list held compactly: what goes in comes out, by place and by path, in order.
#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <string>
#include <vector>

#include "olt/core/hash.h"
#include "olt/model/artifact.h"

using namespace olt;

TEST_CASE("artifact files: each file's path, digest, size and reference come back, sorted by path") {
  ArtifactFiles files;
  const Digest a(sha256_hex("a")), b(sha256_hex("b")), c(sha256_hex("c"));
  files.add("cam/instance/000002.png", a, 2, "frame-2", "instance.png");
  files.add("labels.json", b, 5);
  files.add("cam/class/000002.png", c, 3, "frame-2", "class.png");
  files.add("cam/class/000001.png", a, 1, "frame-1", "class.png");
  files.sort();

  REQUIRE(files.size() == 4);
  std::vector<std::string> paths;
  for (const ListedFile f : files) paths.emplace_back(f.path);
  CHECK(paths == std::vector<std::string>{"cam/class/000001.png", "cam/class/000002.png", "cam/instance/000002.png",
                                          "labels.json"});
  const ListedFile second = files[1];
  CHECK(second.sha256 == c);
  CHECK(second.size == 3);
  CHECK(second.in == "frame-2");
  CHECK(second.as == "class.png");
  CHECK(files[2].in.data() == second.in.data());  // a key held once, met again after another file

  const auto own = files.find("labels.json");
  REQUIRE(own);
  CHECK(own->sha256 == b);
  CHECK(own->size == 5);
  CHECK(own->in.empty());
  CHECK(own->as.empty());
  CHECK(files.place("cam/instance/000002.png") == std::optional<size_t>(2));
  CHECK_FALSE(files.find("cam/class/000003.png"));
  CHECK_FALSE(files.find("cam/class"));  // a prefix is not a file
  CHECK_FALSE(files.find(""));
}

// Guards any later shortcut for a list sorted before (merging what was added, say).
TEST_CASE("artifact files: sorted again after files are added to a sorted list - every file added, in path order") {
  std::mt19937 random(7);
  std::uniform_int_distribution<int> number(0, 99);
  for (int trial = 0; trial < 50; ++trial) {
    CAPTURE(trial);
    ArtifactFiles files;
    std::vector<std::string> paths;
    const auto add = [&](int count) {  // in no order, a path now and then twice
      for (int i = 0; i < count; ++i) {
        paths.push_back("cam/" + std::to_string(number(random)) + ".png");
        files.add(paths.back(), Digest(sha256_hex(paths.back())), paths.size());
      }
    };
    add(number(random));
    files.sort();
    add(trial % 5 == 0 ? 0 : 1 + number(random) % (trial % 2 ? 3 : 60));  // none, a few, or many
    files.sort();
    std::sort(paths.begin(), paths.end());
    REQUIRE(files.size() == paths.size());
    for (size_t i = 0; i < paths.size(); ++i) {
      CHECK(files[i].path == paths[i]);
      CHECK(files[i].sha256 == Digest(sha256_hex(paths[i])));
    }
  }
}

TEST_CASE("artifact files: a copy stands on its own, and adding after sorting keeps each key and name there once") {
  ArtifactFiles files;
  const Digest d(sha256_hex("d"));
  files.add("x/1.png", d, 1, "frame-1", "class.png");
  files.sort();
  ArtifactFiles copy = files;
  files = ArtifactFiles();                               // the original gone: the copy's names and keys are its own
  copy.add("x/0.png", d, 0, "frame-1", "instance.png");  // the same key, after sort() let its index go
  copy.add("x/2.png", d, 2, "frame-2", "class.png");
  copy.sort();
  REQUIRE(copy.size() == 3);
  CHECK(copy[0].path == "x/0.png");
  CHECK(copy[0].in == "frame-1");
  CHECK(copy[1].in == "frame-1");
  CHECK(copy[0].in.data() == copy[1].in.data());  // one copy of the key
  CHECK(copy[2].in == "frame-2");
  CHECK(copy[1].as == "class.png");
  CHECK(copy[2].as == "class.png");
  CHECK(copy[1].as.data() == copy[2].as.data());  // one copy of the name there, before and after sort()
  CHECK(copy[0].as == "instance.png");
  CHECK(copy.bytes() > 0);
}

TEST_CASE("artifact files: a list grown into pages of its own and cut back to the heap keeps its files") {
  ArtifactFiles files;
  const Digest d(sha256_hex("d"));
  for (int i = 0; i < 3000; ++i)  // 3,000 entries of 56 bytes: past the 64 KB where pages begin
    files.add("f/" + std::to_string(100000 + i), d, static_cast<uint64_t>(i), "key-" + std::to_string(i % 10), "x");
  files.sort();
  CHECK(files.bytes() > (64 << 10));
  files.erase_if([](const ListedFile& f) { return f.size % 100 != 0; });  // 30 left
  files.sort();                                                           // its blocks back in the heap
  REQUIRE(files.size() == 30);
  CHECK(files.bytes() > 0);
  const auto last = files.find("f/102900");
  REQUIRE(last);
  CHECK(last->size == 2900);
  CHECK(last->in == "key-0");
  CHECK_FALSE(files.find("f/102901"));
}

TEST_CASE("artifact files: a list of only some files holds those, in order, and only their names") {
  ArtifactFiles files;
  const Digest a(sha256_hex("a")), b(sha256_hex("b"));
  for (int i = 0; i < 100; ++i) {
    const std::string frame = std::to_string(1000 + i);
    files.add("cam/class/" + frame + ".png", a, 2, "frame-" + frame, "class.png");
    files.add("cam/overlay/" + frame + ".jpg", b, 3, "frame-" + frame, "overlay.jpg");
  }
  files.add("labels.json", b, 5);
  files.sort();
  const ArtifactFiles some =
      files.only([](const ListedFile& f) { return f.as == "overlay.jpg" || f.path == "labels.json"; });
  REQUIRE(some.size() == 101);
  CHECK(some[0].path == "cam/overlay/1000.jpg");
  CHECK(some[0].in == "frame-1000");
  CHECK(some[0].sha256 == b);
  CHECK(some[99].path == "cam/overlay/1099.jpg");
  CHECK(some.find("labels.json")->size == 5);
  CHECK_FALSE(some.find("cam/class/1000.png"));
  CHECK(some.bytes() < files.bytes() * 2 / 3);  // the class images' names and entries not held
  CHECK(files.only([](const ListedFile&) { return false; }).empty());
}

TEST_CASE("artifact files: a name too long to hold is refused, not cut") {
  ArtifactFiles files;
  CHECK_THROWS_AS(files.add(std::string(70000, 'a'), Digest(), 0), std::length_error);
  CHECK(files.empty());
}

TEST_CASE("artifact: where a file's bytes are, its own or another artifact's") {
  Artifact a{"k", "", "/cache/objects/k0/k", {}, "/cache/objects"};
  a.files.add("own.txt", Digest(), 1);
  a.files.add("cam/class/1.png", Digest(), 1, "frame-abc", "class.png");
  a.files.sort();
  CHECK(a.path("own.txt") == fs::path("/cache/objects/k0/k/own.txt"));
  CHECK(a.path("cam/class/1.png") == fs::path("/cache/objects/fr/frame-abc/class.png"));
  CHECK(a.path(*a.file("cam/class/1.png")) == fs::path("/cache/objects/fr/frame-abc/class.png"));
  CHECK(a.path("not/listed.txt") == fs::path("/cache/objects/k0/k/not/listed.txt"));
}
