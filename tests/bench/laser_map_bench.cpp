// Times the laser map of a scan log (median of 5 builds) and writes the robot trajectory it found
// and the raw odometry's, as TUM files, for tests/bench/laser_bench.sh to judge.
//   olt_bench_laser_map SCANS ODOMETRY OUT_DIR    -> OUT_DIR/olt_laser_map.tum, OUT_DIR/raw_odometry.tum
// Prints one JSON line: seconds (median), scans, keyframes, loop closures, map points.
// With --threads ROUNDS instead of OUT_DIR: ROUNDS builds with every thread and ROUNDS with one,
// in turn in this one process (the order swapped every round), for laser_threads_bench.sh; prints
// one JSON line: both medians, their ratio, and the quartiles of the rounds' own ratios.
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "olt/core/fs.h"
#include "olt/formats/laser_text.h"
#include "olt/formats/tum.h"
#include "olt/laser/laser_map.h"

using namespace olt;

namespace {

double seconds_to_map(const std::vector<LaserScan>& scans, const std::vector<OdometrySample>& odometry,
                      size_t threads) {
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, threads);
  const auto start = std::chrono::steady_clock::now();
  const LaserMap map = build_laser_map(scans, odometry, LaserMapSettings{});
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The q-quantile, linear between the two values around it (q = 0.5: the median, of an even count
// too).
double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double at = q * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(at);
  if (below + 1 >= values.size()) return values.back();
  return values[below] + (at - static_cast<double>(below)) * (values[below + 1] - values[below]);
}

int threads_in_turn(const std::vector<LaserScan>& scans, const std::vector<OdometrySample>& odometry, int rounds) {
  std::vector<double> every, one, ratios;
  for (int round = 0; round < rounds; ++round) {
    double t_every, t_one;
    if (round % 2 == 0) {
      t_every = seconds_to_map(scans, odometry, 0);
      t_one = seconds_to_map(scans, odometry, 1);
    } else {
      t_one = seconds_to_map(scans, odometry, 1);
      t_every = seconds_to_map(scans, odometry, 0);
    }
    every.push_back(t_every);
    one.push_back(t_one);
    ratios.push_back(t_every / t_one);
  }
  const double m_every = quantile(every, 0.5), m_one = quantile(one, 0.5);
  std::cout << nlohmann::json{{"threads", std::min(static_cast<size_t>(tbb::this_task_arena::max_concurrency()),
                                                   tbb::global_control::active_value(
                                                       tbb::global_control::max_allowed_parallelism))},
                              {"rounds", rounds},
                              {"every_s", m_every},
                              {"one_s", m_one},
                              {"ratio", m_every / m_one},
                              {"round_ratio_q1", quantile(ratios, 0.25)},
                              {"round_ratio_median", quantile(ratios, 0.5)},
                              {"round_ratio_q3", quantile(ratios, 0.75)}}
                   .dump()
            << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4 && !(argc == 5 && std::string(argv[3]) == "--threads")) {
    std::cerr << "usage: olt_bench_laser_map SCANS ODOMETRY OUT_DIR\n"
                 "       olt_bench_laser_map SCANS ODOMETRY --threads ROUNDS\n";
    return 2;
  }
  const std::vector<LaserScan> scans = parse_laser_scans(argv[1], read_file(argv[1]));
  const std::vector<OdometrySample> odometry = parse_odometry(argv[2], read_file(argv[2]));
  if (argc == 5) {
    char* end = nullptr;
    const long rounds = std::strtol(argv[4], &end, 10);
    if (*end != '\0' || rounds < 1 || rounds > 10000) {
      std::cerr << "--threads: expected a number of rounds from 1 to 10000, got '" << argv[4] << "'\n";
      return 2;
    }
    return threads_in_turn(scans, odometry, static_cast<int>(rounds));
  }
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
