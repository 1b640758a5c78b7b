// The tests' main: Catch's, with the thread pool sized as olt's (olt/core/threads.h).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "olt/core/threads.h"

int main(int argc, char** argv) {
  olt::configure_threads();
  return Catch::Session().run(argc, argv);
}
