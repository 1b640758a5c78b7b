#pragma once
// Shared by the libFuzzer targets: bad input must end in InputError (exit code 2, a message naming
// the file); any other exception escaping a parser is a bug, reported as a crash.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "olt/core/error.h"

namespace olt::fuzz {

template <class Parse>
void expect_input_errors_only(const char* target, Parse parse) {
  try {
    parse();
  } catch (const InputError&) {
    // what bad input should get
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: not an InputError: %s\n", target, e.what());
    std::abort();
  }
}

}  // namespace olt::fuzz
