// Times the laser map of a scan log (median of 5 builds) and writes the robot trajectory it found
// and the raw odometry's, as TUM files, for tests/bench/laser_bench.sh to judge.
//   olt_bench_laser_map SCANS ODOMETRY OUT_DIR    -> OUT_DIR/olt_laser_map.tum, OUT_DIR/raw_odometry.tum
// Prints one JSON line: seconds (median), scans, keyframes, loop closures, map points.
#include <algorithm>
#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>

#include "olt/core/fs.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/laser/laser_map.h"

using namespace olt;

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: olt_bench_laser_map SCANS ODOMETRY OUT_DIR\n";
    return 2;
  }
  const std::vector<LaserScan> scans = parse_laser_scans(argv[1], read_file(argv[1]));
  const std::vector<OdometrySample> odometry = parse_odometry(argv[2], read_file(argv[2]));
  std::vector<double> seconds;
  LaserMap result;
  for (int run = 0; run < 5; ++run) {
    const auto start = std::chrono::steady_clock::now();
    result = build_laser_map(scans, odometry, LaserMapSettings{});
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  Trajectory ours, raw;
  int keyframes = 0;
  for (const auto& p : result.poses) {
    ours.push_back({p.timestamp, to_pose3(p.T_map_robot)});
    raw.push_back({p.timestamp, to_pose3(odometry_at(odometry, p.timestamp))});
    keyframes += p.key;
  }
  const fs::path out = argv[3];
  write_file_atomic(out / "olt_laser_map.tum", format_tum_trajectory(ours));
  write_file_atomic(out / "raw_odometry.tum", format_tum_trajectory(raw));
  std::cout << nlohmann::json{{"seconds", seconds[2]},
                              {"scans", scans.size()},
                              {"keyframes", keyframes},
                              {"loop_closures", result.loop_closures},
                              {"map_points", result.map.size()}}
                   .dump()
            << "\n";
  return 0;
}
