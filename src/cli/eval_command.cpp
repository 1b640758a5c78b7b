// `olt eval poses ESTIMATE GROUNDTRUTH`: trajectory error as the TUM benchmark defines it.
// `olt eval labels A B`: in eval_labels_command.cpp.
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <set>

#include "eval_commands.h"
#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/eval/trajectory_error.h"
#include "olt/formats/tum.h"

namespace olt {

void check_flags(const Args& args, const std::string& evaluation, const std::set<std::string>& accepted) {
  for (const auto& [flag, value] : args.flags)
    if (!accepted.count(flag)) throw InputError(flag, "not an option of olt eval " + evaluation);
}

namespace {

int eval_poses(const Args& args) {
  check_flags(args, "poses", {"--json", "--max-dt", "--interpolate", "--plot"});
  const std::string estimate_file = args.positional[1], truth_file = args.positional[2];
  const std::string max_dt_text = args.value("--max-dt", "0.02");
  char* end = nullptr;
  const double max_dt = std::strtod(max_dt_text.c_str(), &end);
  if (*end != '\0' || !(max_dt > 0))
    throw InputError("--max-dt", "expected a positive number of seconds, got '" + max_dt_text + "'");
  const Trajectory estimate = parse_tum_trajectory(estimate_file, read_file(estimate_file));
  const Trajectory truth = parse_tum_trajectory(truth_file, read_file(truth_file));
  const GroundTruthTiming timing =
      args.has("--interpolate") ? GroundTruthTiming::interpolated : GroundTruthTiming::nearest;
  const TrajectoryErrors e = trajectory_errors(estimate, truth, max_dt, timing);
  if (e.matched < 2) throw InputError(estimate_file, "fewer than 2 poses match the ground truth within --max-dt");
  if (args.has("--plot"))
    write_file_atomic(args.value("--plot", ""),
                      encode_png(plot_trajectories(estimate, truth, e.T_groundtruth_estimate, 800)));
  auto stats = [](const ErrorStats& s) {
    return nlohmann::json{{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"max", s.max}, {"count", s.count}};
  };
  if (args.has("--json")) {
    const nlohmann::json out = {{"ground_truth", args.has("--interpolate") ? "interpolated" : "nearest"},
                                {"matched", e.matched},
                                {"estimate_poses", estimate.size()},
                                {"ate_m", stats(e.ate_m)},
                                {"ate_deg", stats(e.ate_deg)},
                                {"rpe_frame_m", stats(e.rpe_frame_m)},
                                {"rpe_frame_deg", stats(e.rpe_frame_deg)},
                                {"rpe_second_m", stats(e.rpe_second_m)},
                                {"rpe_second_deg", stats(e.rpe_second_deg)}};
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    // Each ATE figure after its own alignment (trajectory_error.h): positions for the translation,
    // rotations for the rotation.
    std::printf("matched poses                          %d of %zu\n", e.matched, estimate.size());
    std::printf("ATE RMSE (positions aligned)           %.4f m (median %.4f, max %.4f)\n", e.ate_m.rmse, e.ate_m.median,
                e.ate_m.max);
    std::printf("ATE rotation RMSE (rotations aligned)  %.3f deg (median %.3f, max %.3f)\n", e.ate_deg.rmse,
                e.ate_deg.median, e.ate_deg.max);
    std::printf("RPE per frame  RMSE                    %.4f m  %.3f deg\n", e.rpe_frame_m.rmse, e.rpe_frame_deg.rmse);
    std::printf("RPE per second RMSE                    %.4f m  %.3f deg\n", e.rpe_second_m.rmse,
                e.rpe_second_deg.rmse);
  }
  return kExitOk;
}

}  // namespace

int cmd_eval(const Args& args) {
  if (args.positional[0] == "poses") return eval_poses(args);
  if (args.positional[0] == "labels") return eval_labels(args);
  throw InputError("olt eval", "unknown evaluation '" + args.positional[0] + "' (expected: poses, labels)");
}

}  // namespace olt
