// What a run wrote into the cache, kept by digest for its publishing (src/runtime/written_bytes.h).
#include "runtime/written_bytes.h"

#include <catch2/catch.hpp>
#include <string>

#include "olt/core/hash.h"
#include "support/keeping_memory.h"

using namespace olt;

TEST_CASE("written bytes: kept by digest where memory is kept, within the run's budget, until let go") {
  forget_written();
  const std::string a = "the bytes of a", b = "the bytes of b";
  keep_written(sha256_hex(a), a);  // a process that keeps nothing (`olt run`) keeps none
  CHECK(written_bytes(sha256_hex(a)) == nullptr);
  CHECK(written_room() == 0);

  olt::test::KeepingMemory keeping;
  const size_t room = written_room();
  REQUIRE(room > 0);
  keep_written(sha256_hex(a), a);
  keep_written(sha256_hex(a), a);  // written twice (two stages, one file): kept once
  REQUIRE(written_bytes(sha256_hex(a)) != nullptr);
  CHECK(*written_bytes(sha256_hex(a)) == a);
  CHECK(written_bytes(sha256_hex(b)) == nullptr);
  CHECK(written_room() == room - a.size());

  const std::string too_big(room, 'x');  // more than is left: not kept, and nothing else let go
  keep_written(sha256_hex(too_big), too_big);
  CHECK(written_bytes(sha256_hex(too_big)) == nullptr);
  CHECK(written_bytes(sha256_hex(a)) != nullptr);

  forget_written();
  CHECK(written_bytes(sha256_hex(a)) == nullptr);
  CHECK(written_room() == room);
}
