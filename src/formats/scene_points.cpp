#include "olt/formats/scene_points.h"

#include <cstring>

#include "olt/core/error.h"
#include "olt/core/huge_pages.h"

namespace olt {
namespace {

constexpr std::string_view kMagic = "OLTPTS1\n";
constexpr size_t kHeader = kScenePointsHeaderBytes, kPoint = 16;

// The host is little-endian (x86-64, aarch64), as the format is: fields are copied as they are.
template <typename T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
T get(std::string_view bytes, size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

}  // namespace

std::string encode_scene_points(const ScenePoints& points) {
  std::string out;
  out.reserve(kHeader + kPoint * points.cloud.size());
  advise_huge_pages(out.data(), out.capacity());  // before they are first written
  out += kMagic;
  put<uint64_t>(out, points.cloud.size());
  put<float>(out, points.voxel_size_m);
  for (const auto& p : points.cloud) {
    put(out, p.x), put(out, p.y), put(out, p.z);
    out += {static_cast<char>(p.r), static_cast<char>(p.g), static_cast<char>(p.b), '\0'};
  }
  return out;
}

float decode_scene_voxel_size(std::string_view head, const std::string& file) {
  if (head.size() < kHeader || head.substr(0, kMagic.size()) != kMagic)
    throw InputError(file, "not a scene_points.bin (no OLTPTS1 header)");
  return get<float>(head, 16);
}

ScenePoints decode_scene_points(std::string_view bytes, const std::string& file) {
  const float voxel_size_m = decode_scene_voxel_size(bytes, file);
  const auto count = get<uint64_t>(bytes, 8);
  if ((bytes.size() - kHeader) / kPoint != count || (bytes.size() - kHeader) % kPoint != 0)
    throw InputError(file, "says " + std::to_string(count) + " points but holds " +
                               std::to_string(bytes.size() - kHeader) + " bytes of them (16 per point)");
  ScenePoints points;
  points.voxel_size_m = voxel_size_m;
  points.cloud.reserve(count);
  advise_huge_pages(points.cloud.data(), count * sizeof(ColoredPoint));  // before they are first written
  points.cloud.resize(count);
  for (size_t i = 0; i < count; ++i) {
    const size_t at = kHeader + i * kPoint;
    ColoredPoint& p = points.cloud[i];
    p.x = get<float>(bytes, at), p.y = get<float>(bytes, at + 4), p.z = get<float>(bytes, at + 8);
    p.r = static_cast<uint8_t>(bytes[at + 12]), p.g = static_cast<uint8_t>(bytes[at + 13]);
    p.b = static_cast<uint8_t>(bytes[at + 14]);
  }
  return points;
}

}  // namespace olt
