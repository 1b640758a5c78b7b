// scene_points.bin: what is written is read back exactly; a file of another kind is refused by name.
#include "olt/formats/scene_points.h"

#include <catch2/catch.hpp>

#include "olt/core/error.h"

using namespace olt;

TEST_CASE("scene_points.bin: points, colours and voxel size read back as written") {
  ScenePoints points{{{1.5f, -2.25f, 0.125f, 255, 0, 7}, {0, 0, 3e-7f, 1, 2, 3}}, 0.02f};
  const std::string bytes = encode_scene_points(points);
  CHECK(bytes.size() == 20 + 2 * 16);
  const ScenePoints back = decode_scene_points(bytes, "scene_points.bin");
  CHECK(back.voxel_size_m == 0.02f);
  REQUIRE(back.cloud.size() == 2);
  CHECK(back.cloud[0].y == -2.25f);
  CHECK(back.cloud[1].z == 3e-7f);
  CHECK(int(back.cloud[0].r) == 255);
  CHECK(int(back.cloud[0].b) == 7);
  CHECK(int(back.cloud[1].g) == 2);
}

TEST_CASE("scene_points.bin: another file or a truncated one is refused") {
  CHECK_THROWS_AS(decode_scene_points("ply\nformat binary", "scene.ply"), InputError);
  const std::string bytes = encode_scene_points({{{1, 2, 3, 4, 5, 6}}, 0.01f});
  CHECK_THROWS_WITH(decode_scene_points(bytes.substr(0, bytes.size() - 1), "x.bin"), Catch::Contains("says 1 points"));
}

TEST_CASE("scene_points.bin: the voxel size is read from the header alone, or refused by name") {
  const std::string bytes = encode_scene_points({{{1, 2, 3, 4, 5, 6}}, 0.035f});
  CHECK(decode_scene_voxel_size(bytes.substr(0, kScenePointsHeaderBytes), "scene_points.bin") == 0.035f);
  CHECK_THROWS_WITH(decode_scene_voxel_size(bytes.substr(0, kScenePointsHeaderBytes - 1), "a/scene_points.bin"),
                    Catch::Contains("a/scene_points.bin") && Catch::Contains("no OLTPTS1 header"));
  CHECK_THROWS_WITH(decode_scene_voxel_size("OLTPTS2\n" + bytes.substr(8, 12), "b.bin"),
                    Catch::Contains("b.bin") && Catch::Contains("no OLTPTS1 header"));
}
