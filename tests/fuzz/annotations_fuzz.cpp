// libFuzzer target: an annotation file in every box format (native and each tool's importer).
#include <cstdint>
#include <string>

#include "fuzz_input.h"
#include "olt/formats/box_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const auto& format : olt::box_formats())
    olt::fuzz::expect_input_errors_only(format.c_str(), [&] { olt::read_boxes(format, "boxes.json", text); });
  return 0;
}
