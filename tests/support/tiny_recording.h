#pragma once
// A small valid TUM recording written by tests: 3 frames of 64x48 depth (1.0, 1.02, 1.04 m at
// 5000 units per metre) and colour, and a ground-truth trajectory around them.
#include <filesystem>

namespace olt::test {

/// Writes depth/, rgb/, depth.txt, rgb.txt and groundtruth.txt into `dir`.
void write_tiny_tum_recording(const std::filesystem::path& dir);

}  // namespace olt::test
