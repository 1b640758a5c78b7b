#include "support/synthetic_truth.h"

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/formats/tum.h"

namespace olt::test {

SyntheticJudgement judge_synthetic_run(const std::filesystem::path& out, const std::string& poses_stage,
                                       const SyntheticConfig& config) {
  const SyntheticScene scene = make_synthetic_scene(config);
  const auto label_map = nlohmann::json::parse(read_file(out / "labels.json"));
  std::map<std::string, int> class_id;
  for (const auto& c : label_map["classes"]) class_id[c["name"]] = c["id"];

  // Published poses by sensor and timestamp (6 decimals, as written).
  std::map<std::string, std::map<long long, Pose>> published;
  for (const auto& sensor : scene.sensors) {
    const fs::path file = out / poses_stage / ("trajectory_" + sensor + ".txt");
    for (const auto& s : parse_tum_trajectory(file.string(), read_file(file)))
      published[sensor][std::llround(s.timestamp * 1e6)] = s.pose;
  }
  SyntheticJudgement j;
  double t2 = 0, r2 = 0;
  int64_t agree = 0;
  for (size_t i = 0; i < scene.timestamps.size(); ++i) {
    const std::string& sensor = scene.sensors[static_cast<size_t>(scene.camera_of[i])];
    const auto found = published[sensor].find(std::llround(scene.timestamps[i] * 1e6));
    if (found == published[sensor].end()) continue;  // flagged
    ++j.observations;
    const Pose error = scene.T_world_camera[i].inverse() * found->second;
    const double t = error.translation().norm(), r = rotation_angle(error) * 180 / M_PI;
    t2 += t * t;
    r2 += r * r;
    j.translation_max_m = std::max(j.translation_max_m, t);
    j.rotation_max_deg = std::max(j.rotation_max_deg, r);

    char id[16];
    std::snprintf(id, sizeof(id), "%06zu", i);
    const fs::path labels_file = out / "labels" / sensor / "class" / (std::string(id) + ".png");
    if (!fs::exists(labels_file)) continue;
    const cv::Mat labels = read_png_u16(labels_file);
    const SyntheticFrame truth = render_synthetic_frame(scene, i);
    for (int v = 0; v < labels.rows; ++v)
      for (int u = 0; u < labels.cols; ++u) {
        if (labels.at<uint16_t>(v, u) == 65535) continue;  // no depth
        const int object = truth.object.at<uint16_t>(v, u);
        const int expected = object == 0 ? 0 : class_id.at(scene.objects[object - 1].label);
        ++j.depth_pixels;
        agree += labels.at<uint16_t>(v, u) == expected;
      }
  }
  if (j.observations > 0) {
    j.translation_rmse_m = std::sqrt(t2 / j.observations);
    j.rotation_rmse_deg = std::sqrt(r2 / j.observations);
  }
  j.label_agreement = j.depth_pixels > 0 ? static_cast<double>(agree) / static_cast<double>(j.depth_pixels) : 0;
  return j;
}

}  // namespace olt::test
