// What a run keeps of the files it wrote, by their digests (olt/core/run_memory.h).
#include "olt/core/run_memory.h"

#include <catch2/catch.hpp>
#include <string>

#include "olt/core/hash.h"
#include "support/keeping_memory.h"

using namespace olt;

namespace {

struct Parsed {
  int value = 0;
};

void keep_bytes(const std::string& bytes) {
  keep_for_run<std::string>(sha256_hex(bytes), std::make_shared<const std::string>(bytes), bytes.size());
}

}  // namespace

TEST_CASE("run memory: kept by digest and type where memory is kept, within the run's budget, until let go") {
  forget_run_memory();
  const std::string a = "the bytes of a", b = "the bytes of b";
  keep_bytes(a);  // a process that keeps nothing (`olt run`) keeps none
  CHECK(kept_for_run<std::string>(sha256_hex(a)) == nullptr);
  CHECK(run_memory_room() == 0);

  olt::test::KeepingMemory keeping;
  REQUIRE(run_memory_room() == kRunMemoryBudget);
  keep_bytes(a);
  keep_bytes(a);  // a file written twice (two stages, one file): kept once, counted once
  REQUIRE(kept_for_run<std::string>(sha256_hex(a)) != nullptr);
  CHECK(*kept_for_run<std::string>(sha256_hex(a)) == a);
  CHECK(kept_for_run<std::string>(sha256_hex(b)) == nullptr);
  CHECK(run_memory_room() == kRunMemoryBudget - a.size() - kRunMemoryEntryBytes);

  // What a stage parsed of the same file, beside its bytes: found by its own type only.
  keep_for_run<Parsed>(sha256_hex(a), std::make_shared<const Parsed>(Parsed{7}), sizeof(Parsed));
  REQUIRE(kept_for_run<Parsed>(sha256_hex(a)) != nullptr);
  CHECK(kept_for_run<Parsed>(sha256_hex(a))->value == 7);
  CHECK(kept_for_run<Parsed>(sha256_hex(b)) == nullptr);

  // The budget: what fills it exactly is kept, one byte more is not (and nothing else goes).
  const size_t room = run_memory_room();
  keep_for_run<Parsed>(sha256_hex(b), std::make_shared<const Parsed>(), room - kRunMemoryEntryBytes + 1);
  CHECK(kept_for_run<Parsed>(sha256_hex(b)) == nullptr);
  keep_for_run<Parsed>(sha256_hex(b), std::make_shared<const Parsed>(), room - kRunMemoryEntryBytes);
  CHECK(kept_for_run<Parsed>(sha256_hex(b)) != nullptr);
  CHECK(run_memory_room() == 0);
  CHECK(kept_for_run<std::string>(sha256_hex(a)) != nullptr);

  forget_run_memory();
  CHECK(kept_for_run<std::string>(sha256_hex(a)) == nullptr);
  CHECK(kept_for_run<Parsed>(sha256_hex(a)) == nullptr);
  CHECK(run_memory_room() == kRunMemoryBudget);
}
