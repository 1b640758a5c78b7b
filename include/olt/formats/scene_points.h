#pragma once
// scene_points.bin: the reconstruct stage's cloud kept for stages downstream that draw it (the
// report), in a form read without PCL. Little-endian:
//   8 bytes  "OLTPTS1\n"
//   uint64   point count N
//   float32  voxel size, metres (how wide a point is drawn)
//   N x 16 bytes: float32 x, y, z (metres, annotation frame), uint8 r, g, b, one zero byte
#include <string>
#include <string_view>

#include "olt/model/cloud.h"

namespace olt {

struct ScenePoints {
  ColoredCloud cloud;
  float voxel_size_m = 0;
};

std::string encode_scene_points(const ScenePoints& points);
/// Throws InputError naming `file` when the bytes are not a scene_points.bin.
ScenePoints decode_scene_points(std::string_view bytes, const std::string& file);

}  // namespace olt
