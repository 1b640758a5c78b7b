#pragma once
// scene_points.bin: the reconstruct stage's cloud kept for stages downstream that draw it (the
// report), in a form read without PCL. Little-endian:
//   8 bytes  "OLTPTS1\n"
//   uint64   point count N
//   float32  voxel size, metres (how wide a point is drawn)
//   N x 16 bytes: float32 x, y, z (metres, annotation frame), uint8 r, g, b, one zero byte
#include <cstddef>
#include <string>
#include <string_view>

#include "olt/model/cloud.h"

namespace olt {

struct ScenePoints {
  ColoredCloud cloud;
  float voxel_size_m = 0;
};

/// Bytes before the first point: what decode_scene_voxel_size reads.
constexpr size_t kScenePointsHeaderBytes = 8 + 8 + 4;

std::string encode_scene_points(const ScenePoints& points);
/// The voxel size from the file's first kScenePointsHeaderBytes (no point decoded). Throws
/// InputError naming `file` when they are not a scene_points.bin's.
float decode_scene_voxel_size(std::string_view head, const std::string& file);
/// Throws InputError naming `file` when the bytes are not a scene_points.bin.
ScenePoints decode_scene_points(std::string_view bytes, const std::string& file);

}  // namespace olt
