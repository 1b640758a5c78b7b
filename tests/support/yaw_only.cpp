#include "support/yaw_only.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"

namespace olt::test {

std::vector<Box> yaw_only(std::vector<Box> boxes, const Pose& T_world_frame) {
  for (auto& b : boxes) {
    const Pose T_frame_box = T_world_frame.inverse() * b.T_world_box;
    const Eigen::Vector3d x = T_frame_box.linear().col(0);
    Pose drawn = Pose::Identity();
    drawn.linear() = Eigen::AngleAxisd(std::atan2(x.y(), x.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    drawn.translation() = T_frame_box.translation();
    b.T_world_box = drawn;
  }
  return boxes;
}

namespace {

std::vector<Eigen::Vector3d> read_pcd_points(const std::filesystem::path& file) {
  const std::string bytes = read_text(file);
  const auto data = bytes.find("DATA binary\n");
  REQUIRE(data != std::string::npos);
  REQUIRE(bytes.find("FIELDS x y z rgb") != std::string::npos);
  std::vector<Eigen::Vector3d> points;
  for (size_t at = data + 12; at + 16 <= bytes.size(); at += 16) {
    float xyz[3];
    std::memcpy(xyz, bytes.data() + at, sizeof(xyz));
    points.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  return points;
}

}  // namespace

std::vector<Box> yaw_only_refitted(std::vector<Box> boxes, const Pose& T_world_frame,
                                   const std::filesystem::path& scene_pcd) {
  const std::vector<Eigen::Vector3d> scene = read_pcd_points(scene_pcd);
  const std::vector<Box> turned = yaw_only(boxes, T_world_frame);
  for (size_t k = 0; k < boxes.size(); ++k) {
    const Pose T_box_frame = (T_world_frame.inverse() * boxes[k].T_world_box).inverse();
    const Pose T_yaw_frame = turned[k].T_world_box.inverse();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (const auto& p : scene) {
      if (((T_box_frame * p).cwiseAbs() - boxes[k].size / 2).maxCoeff() > 0) continue;
      const Eigen::Vector3d q = T_yaw_frame * p;
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    boxes[k].T_world_box = turned[k].T_world_box;
    if (!(lo.array() <= hi.array()).all()) continue;
    boxes[k].T_world_box.translation() = turned[k].T_world_box * ((lo + hi) / 2);
    boxes[k].size = (hi - lo).cwiseMax(1e-3);
  }
  return boxes;
}

double label_agreement(const std::filesystem::path& a, const std::filesystem::path& b) {
  const auto result = run_olt("eval labels " + a.string() + " " + b.string() + " --json");
  INFO(result.err);
  REQUIRE(result.exit_code == 0);
  return nlohmann::json::parse(result.out).at("agreement").get<double>();
}

}  // namespace olt::test
