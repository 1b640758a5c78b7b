// Registration benchmark on a TUM RGB-D folder: runs one option set of the registration odometry
// over every depth image, prints one JSON line with accuracy (ATE, RPE per frame and per second),
// median milliseconds per frame (depth image decoding excluded) and peak resident memory.
//   olt_bench_registration DATASET_DIR NAME [key=value ...]   (keys as in the poses stage)
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "olt/core/allocator.h"
#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/eval/trajectory_error.h"
#include "olt/formats/tum.h"
#include "olt/poses/registration_poses.h"
#include "olt/source/associate.h"

using namespace olt;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s DATASET_DIR NAME [key=value ...]\n", argv[0]);
    return 2;
  }
  keep_freed_memory();  // as olt does
  try {
    const fs::path dir = argv[1];
    RegistrationPosesConfig config;
    double time_offset_s = -0.02;  // for the corrected figures: added to the depth timestamps (calibrate's parameter)
    std::string trajectory_out;    // where to write the estimate (TUM format), if anywhere
    for (int i = 3; i < argc; ++i) {
      const std::string arg = argv[i];
      const auto eq = arg.find('=');
      const std::string key = arg.substr(0, eq), value = arg.substr(eq + 1);
      if (key == "algorithm")
        config.solver.method = value == "icp" ? RegistrationMethod::icp : RegistrationMethod::gicp;
      else if (key == "memory")
        config.memory = value == "previous"    ? RegistrationMemory::previous
                        : value == "local_map" ? RegistrationMemory::local_map
                                               : RegistrationMemory::keyframes;
      else if (key == "memory_size")
        config.memory_size = std::stoi(value);
      else if (key == "voxel_size_m")
        config.voxel_size_m = std::stod(value);
      else if (key == "photometric_weight")
        config.photometric_weight = std::stod(value);
      else if (key == "photometric_halvings")
        config.photometric_halvings = std::stoi(value);
      else if (key == "photometric_min_gradient")
        config.photometric_min_gradient = std::stod(value);
      else if (key == "photometric_huber")
        config.photometric_huber = std::stod(value);
      else if (key == "pixel_stride")
        config.pixel_stride = std::stoi(value);
      else if (key == "smoothing")
        config.smoothing = value == "true";
      else if (key == "key_distance_m")
        config.key_distance_m = std::stod(value);
      else if (key == "key_angle_deg")
        config.key_angle_deg = std::stod(value);
      else if (key == "max_iterations")
        config.solver.max_iterations = std::stoi(value);
      else if (key == "trajectory_out")
        trajectory_out = value;
      else if (key == "time_offset_s")
        time_offset_s = std::stod(value);
      else if (key == "max_correspondence_m")
        config.solver.max_correspondence_m = std::stod(value);
      else if (key == "loop_candidates")
        config.loop_candidates = std::stoi(value);
      else if (key == "keyframe_distance_m")
        config.keyframe_distance_m = std::stod(value);
      else if (key == "keyframe_angle_deg")
        config.keyframe_angle_deg = std::stod(value);
      else
        throw std::invalid_argument("unknown option " + key);
    }
    SensorCalibration cal;  // TUM fr1 (published), depth registered to colour
    cal.depth = {640, 480, 517.3, 516.5, 318.6, 255.3, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}};
    cal.color = cal.depth;
    cal.depth_scale = 5000;
    const auto list = parse_tum_list((dir / "depth.txt").string(), read_file(dir / "depth.txt"));
    const auto colors = parse_tum_list((dir / "rgb.txt").string(), read_file(dir / "rgb.txt"));
    std::vector<double> depth_times, color_times;
    for (const auto& e : list) depth_times.push_back(e.timestamp);
    for (const auto& e : colors) color_times.push_back(e.timestamp);
    const auto color_of = associate_nearest(depth_times, color_times, 0.02);
    const Trajectory truth =
        parse_tum_trajectory((dir / "groundtruth.txt").string(), read_file(dir / "groundtruth.txt"));
    RegistrationOdometry odometry({{"kinect", cal}}, config, Pose::Identity());
    std::vector<double> ms;
    for (size_t i = 0; i < list.size(); ++i) {
      const TumListEntry& e = list[i];
      const cv::Mat depth = read_grey16(dir / e.file);
      // Decoded before the clock starts, as the depth image: image decoding is not timed.
      const cv::Mat color = color_of[i] ? read_color(dir / colors[*color_of[i]].file) : cv::Mat();
      const auto start = std::chrono::steady_clock::now();
      std::optional<ImageFile> color_file;
      double color_dt_s = 0;
      if (color_of[i]) {
        color_file = ImageFile{colors[*color_of[i]].file, Digest()};
        color_dt_s = colors[*color_of[i]].timestamp - e.timestamp;
      }
      odometry.add({e.stamp_text, "kinect", e.timestamp, {e.file, Digest()}, color_file, color_dt_s}, depth,
                   [&] { return color; });
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    // The last pose-graph optimisation, shared out over the frames.
    const auto finish_start = std::chrono::steady_clock::now();
    const std::vector<ObservationPose> poses = odometry.finish();
    const double finish_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - finish_start).count();
    for (double& m : ms) m += finish_ms / static_cast<double>(ms.size());
    Trajectory estimate;
    for (const auto& p : poses) estimate.push_back({p.timestamp, p.T_world_sensor});
    if (!trajectory_out.empty()) write_file_atomic(trajectory_out, format_tum_trajectory(estimate));
    // As the TUM benchmark defines it: depth timestamps, nearest ground-truth sample.
    const TrajectoryErrors errors = trajectory_errors(estimate, truth, 0.02);
    // Corrected: the depth clock's lag removed and the ground truth interpolated.
    Trajectory shifted = estimate;
    for (auto& s : shifted) s.timestamp += time_offset_s;
    const TrajectoryErrors corrected = trajectory_errors(shifted, truth, 0.02, GroundTruthTiming::interpolated);
    std::sort(ms.begin(), ms.end());
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const nlohmann::json out = {{"name", argv[2]},
                                {"frames", list.size()},
                                {"ate_m", errors.ate_m.rmse},
                                {"rpe_frame_deg", errors.rpe_frame_deg.rmse},
                                {"rpe_frame_m", errors.rpe_frame_m.rmse},
                                {"rpe_second_deg", errors.rpe_second_deg.rmse},
                                {"rpe_second_m", errors.rpe_second_m.rmse},
                                {"corrected",
                                 {{"ate_m", corrected.ate_m.rmse},
                                  {"rpe_frame_deg", corrected.rpe_frame_deg.rmse},
                                  {"rpe_second_deg", corrected.rpe_second_deg.rmse}}},
                                {"median_ms", ms[ms.size() / 2]},
                                {"peak_mb", usage.ru_maxrss / 1024.0}};
    std::printf("%s\n", out.dump().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
