#pragma once
// Boxes as drawn by a tool that turns boxes about z only (labelCloud's default), for the tests of
// the annotation frame.
#include <filesystem>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/geometry.h"

namespace olt::test {

/// Each box's pose in `frame` (T_world_frame) with its roll and pitch dropped: T_world_box then
/// holds the pose in that frame, as a file drawn there says it.
std::vector<Box> yaw_only(std::vector<Box> boxes, const Pose& T_world_frame);

/// Yaw-only boxes refitted to the scene, as an annotator draws them in `frame`: each box turned
/// about z only, then shrunk or grown to the points of `scene_pcd` (a binary PCD of x y z rgb in
/// that frame, as the reconstruct stage publishes) that the original box holds; boxes holding no
/// point are only turned. T_world_box then holds the pose in `frame`.
std::vector<Box> yaw_only_refitted(std::vector<Box> boxes, const Pose& T_world_frame,
                                   const std::filesystem::path& scene_pcd);

/// `olt eval labels A B --json`'s agreement: the share of pixels labeled in either output that carry
/// the same class in both.
double label_agreement(const std::filesystem::path& a, const std::filesystem::path& b);

}  // namespace olt::test
