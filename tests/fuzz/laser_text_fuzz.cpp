// libFuzzer target: the robot's text inputs, each parser on the same bytes: laser scans, odometry,
// laser maps, the plain-text layout's sequence file and scan file.
#include <cstdint>
#include <string>

#include "fuzz_input.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/plain_text_layout.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  using olt::fuzz::expect_input_errors_only;
  expect_input_errors_only("laser scans", [&] {
    for (const auto& scan : olt::parse_laser_scans("scans.txt", text)) olt::scan_points(scan, 0.1, 30);
  });
  expect_input_errors_only("odometry", [&] { olt::parse_odometry("odometry.txt", text); });
  expect_input_errors_only("laser map", [&] { olt::parse_point_map("map.txt", text); });
  expect_input_errors_only("plain-text sequence", [&] { olt::parse_plain_text_sequence("seq.txt", text); });
  expect_input_errors_only("plain-text scan", [&] {
    olt::scan_points(olt::parse_plain_text_scan("0_scan.txt", text, olt::PlainTextEntry{}), 0.1, 30);
  });
  return 0;
}
