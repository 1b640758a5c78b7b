// libFuzzer target: a TUM trajectory (timestamp tx ty tz qx qy qz qw).
#include <cstdint>
#include <string>

#include "fuzz_input.h"
#include "olt/formats/tum.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  olt::fuzz::expect_input_errors_only("trajectory", [&] { olt::parse_tum_trajectory("trajectory.txt", text); });
  return 0;
}
