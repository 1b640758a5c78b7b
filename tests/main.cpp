// The tests' main: Catch's, after the same OpenMP wait policy as olt's (olt/core/parallel.h).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "olt/core/parallel.h"

int main(int argc, char** argv) {
  olt::wait_passively(argv);
  return Catch::Session().run(argc, argv);
}
