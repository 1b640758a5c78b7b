// libFuzzer target: a TUM image list (rgb.txt, depth.txt).
#include <cstdint>
#include <string>

#include "fuzz_input.h"
#include "olt/formats/tum.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  olt::fuzz::expect_input_errors_only("tum_list", [&] { olt::parse_tum_list("depth.txt", text); });
  return 0;
}
