// HeapOptional: optional's behaviour, its value on the heap.
#include "olt/core/heap_optional.h"

#include <catch2/catch.hpp>
#include <string>

using namespace olt;

TEST_CASE("heap optional: a pointer's size - copies are values of their own, a moved-from one is empty") {
  static_assert(sizeof(HeapOptional<std::string>) == sizeof(void*));
  HeapOptional<std::string> a;
  CHECK_FALSE(a);
  CHECK_THROWS_AS(a.value(), std::bad_optional_access);
  a = std::string("first");
  REQUIRE(a.has_value());
  HeapOptional<std::string> b = a;  // a copy, not a shared value
  b->append(" and more");
  CHECK(*a == "first");
  CHECK(*b == "first and more");
  a = b;
  CHECK(a.value() == "first and more");
  const HeapOptional<std::string>& itself = a;
  a = itself;  // assigning itself keeps the value
  CHECK(*a == "first and more");
  HeapOptional<std::string> c = std::move(b);
  CHECK(*c == "first and more");
  CHECK_FALSE(b);  // NOLINT(bugprone-use-after-move): what a move leaves is part of the contract
  c = std::nullopt;
  CHECK_FALSE(c);
  CHECK(c.emplace(3, 'x') == "xxx");
  const HeapOptional<std::string> empty;
  c = empty;
  CHECK_FALSE(c.has_value());
}
