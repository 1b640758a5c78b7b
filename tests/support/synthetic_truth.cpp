#include "support/synthetic_truth.h"

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/formats/tum.h"

namespace olt::test {
namespace {

// Values by sensor, found by timestamp to within 0.1 ms (a recording may round its timestamps).
template <class T>
class ByTime {
 public:
  void add(const std::string& sensor, double t, T value) { items_[sensor].emplace(t, std::move(value)); }
  const T* find(const std::string& sensor, double t) const {
    const auto s = items_.find(sensor);
    if (s == items_.end()) return nullptr;
    const auto it = s->second.lower_bound(t - 1e-4);
    return it != s->second.end() && it->first <= t + 1e-4 ? &it->second : nullptr;
  }

 private:
  std::map<std::string, std::map<double, T>> items_;
};

}  // namespace

SyntheticJudgement judge_synthetic_run(const std::filesystem::path& out, const std::string& poses_stage,
                                       const SyntheticConfig& config, const Pose& T_world_output) {
  const SyntheticScene scene = make_synthetic_scene(config);
  const auto label_map = nlohmann::json::parse(read_file(out / "labels.json"));
  std::map<std::string, int> class_id;
  for (const auto& c : label_map["classes"]) class_id[c["name"]] = c["id"];

  ByTime<Pose> published;  // each sensor's published trajectory (flagged observations are not in it)
  for (const auto& sensor : scene.sensors) {
    const fs::path file = out / poses_stage / ("trajectory_" + sensor + ".txt");
    for (const auto& s : parse_tum_trajectory(file.string(), read_file(file)))
      published.add(sensor, s.timestamp, s.pose);
  }
  ByTime<fs::path> class_images;  // from the manifest
  const auto manifest = nlohmann::json::parse(read_file(out / "manifest.json"));
  for (const auto& f : manifest["files"])
    if (f["kind"] == "class_label")
      class_images.add(f["sensor"], f["observation"]["timestamp"], out / f["path"].get<std::string>());

  SyntheticJudgement j;
  double t2 = 0, r2 = 0;
  int64_t agree = 0;
  for (size_t i = 0; i < scene.timestamps.size(); ++i) {
    const std::string& sensor = scene.sensors[static_cast<size_t>(scene.camera_of[i])];
    const Pose* pose = published.find(sensor, scene.timestamps[i]);
    if (!pose) continue;  // flagged
    ++j.observations;
    const Pose error = scene.T_world_camera[i].inverse() * T_world_output * *pose;
    const double t = error.translation().norm(), r = rotation_angle(error) * 180 / M_PI;
    t2 += t * t;
    r2 += r * r;
    j.translation_max_m = std::max(j.translation_max_m, t);
    j.rotation_max_deg = std::max(j.rotation_max_deg, r);

    const fs::path* labels_file = class_images.find(sensor, scene.timestamps[i]);
    if (!labels_file) continue;
    const cv::Mat labels = read_grey16(*labels_file);
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
