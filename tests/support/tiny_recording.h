#pragma once
// A small valid TUM recording written by tests: 3 frames of 64x48 depth (1.0, 1.02, 1.04 m at
// 5000 units per metre) and colour, and a ground-truth trajectory around them.
#include <filesystem>
#include <string>

namespace olt::test {

/// Writes depth/, rgb/, depth.txt, rgb.txt and groundtruth.txt into `dir`; colour images in the
/// format of `color_extension` (".png", ".jpg", ".bmp", ".tiff").
void write_tiny_tum_recording(const std::filesystem::path& dir, const std::string& color_extension = ".png");

/// A job labeling the recording written into `data` beside it with the box of kTinyTumBoxes (in
/// `boxes.json`): source, calibrate, poses, scene, annotations and labels; output `out`, cache `cache`.
extern const char* const kTinyTumJob;
/// One box, 0.5 m a side, 1 m in front of the camera.
extern const char* const kTinyTumBoxes;

/// Writes the recording (colour as `color_extension`), `job` and `boxes` (boxes.json) into `root`,
/// runs the job (REQUIREs exit 0) and returns olt's stderr.
std::string run_tiny_tum_job(const std::filesystem::path& root, const std::string& job,
                             const std::string& boxes = kTinyTumBoxes, const std::string& color_extension = ".png");

}  // namespace olt::test
