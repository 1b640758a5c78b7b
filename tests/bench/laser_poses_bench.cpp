// Laser poses on the synthetic 4-camera robot: runs a job (jobs/synthetic_robot_laser.yaml) with
// `refine: none` and `refine: registration` and judges each against the exact truth: camera pose
// errors and class label agreement on pixels with depth.
//   olt_bench_laser_poses OLT_BINARY JOB_FILE
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include "support/synthetic_truth.h"

using namespace olt;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: olt_bench_laser_poses OLT_BINARY JOB_FILE\n";
    return 2;
  }
  const std::filesystem::path job_file = std::filesystem::absolute(argv[2]);
  const std::filesystem::path work = std::filesystem::temp_directory_path() / "olt_bench_laser_poses";
  std::filesystem::remove_all(work);
  std::filesystem::create_directories(work);
  std::printf("%-28s %6s %9s %9s %9s %9s %8s %7s\n", "synthetic robot, 4 cameras", "poses", "t RMSE m", "t max m",
              "r RMSE deg", "r max deg", "labels %", "poses s");
  for (const std::string refine : {"none", "registration"}) {
    YAML::Node job = YAML::LoadFile(job_file.string());
    job["output"] = (work / ("out_" + refine)).string();
    job["cache"] = (work / "cache").string();
    job["stages"]["source"]["params"]["path"] = YAML::Node();  // keep the job's synthetic settings
    job["stages"]["source"]["params"].remove("path");
    job["stages"]["poses"]["params"]["refine"] = refine;
    const std::filesystem::path file = work / ("job_" + refine + ".yaml");
    std::ofstream(file) << job;
    const auto start = std::chrono::steady_clock::now();
    const std::string command =
        std::string(argv[1]) + " run " + file.string() + " > " + (work / "log.txt").string() + " 2>&1";
    if (std::system(command.c_str()) != 0) {
      std::cerr << "olt run failed; see " << (work / "log.txt") << "\n";
      return 1;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto& p = job["stages"]["source"]["params"];
    SyntheticConfig config;
    config.cameras = p["cameras"].as<int>();
    config.frames = p["frames"].as<int>();
    config.rate_hz = p["rate_hz"].as<double>();
    config.width = p["width"].as<int>();
    config.height = p["height"].as<int>();
    if (p["seed"]) config.seed = p["seed"].as<unsigned>();
    const test::SyntheticJudgement j = test::judge_synthetic_run(work / ("out_" + refine), "poses", config);
    std::printf("%-28s %6d %9.4f %9.4f %9.3f %9.3f %8.2f %7.1f\n", ("laser, refine: " + refine).c_str(), j.observations,
                j.translation_rmse_m, j.translation_max_m, j.rotation_rmse_deg, j.rotation_max_deg,
                100 * j.label_agreement, seconds);
  }
  std::printf(
      "(pose errors against the exact camera poses; labels: class agreement on pixels with depth; "
      "poses s: the whole olt run, cold cache for the first row)\n");
  return 0;
}
