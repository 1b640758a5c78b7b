#include "olt/cli/commands.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>

#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/eval/trajectory_error.h"
#include "olt/formats/tum.h"
#include "olt/job/job.h"
#include "olt/runtime/runner.h"
#include "olt/stages/stage.h"

#ifndef OLT_VERSION
#define OLT_VERSION "dev"
#endif

namespace olt {
namespace {

struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> flags;  ///< "--json" -> "", "--max-dt" -> "0.02"
  bool has(const std::string& flag) const { return flags.count(flag) > 0; }
  std::string value(const std::string& flag, const std::string& fallback) const {
    auto it = flags.find(flag);
    return it == flags.end() ? fallback : it->second;
  }
};

struct Command {
  const char* name;
  const char* usage;
  const char* summary;
  std::vector<std::string> flags;  ///< accepted flags besides --help; "--name=" takes a value
  size_t positional;               ///< number of positional arguments
  std::function<int(const Args&)> run;
};

Job load(const Args& args) { return load_job(args.positional.at(0), kind_specs()); }

int cmd_validate(const Args& args) {
  const Job job = load(args);
  std::printf("%s: valid (%zu stages)\n", job.file.c_str(), job.stages.size());
  return kExitOk;
}

int cmd_plan(const Args& args) {
  const Job job = load(args);
  const auto plan = plan_job(job);
  if (args.has("--json")) {
    nlohmann::json stages = nlohmann::json::array();
    for (const auto& s : plan)
      stages.push_back({{"id", s.id}, {"kind", s.kind}, {"status", s.status}, {"reason", s.reason}});
    std::printf("%s\n", nlohmann::json{{"stages", stages}}.dump(2).c_str());
  } else {
    for (const auto& s : plan)
      std::printf("%-16s %-12s %-7s %s\n", s.id.c_str(), s.kind.c_str(), s.status.c_str(), s.reason.c_str());
  }
  return kExitOk;
}

int cmd_run(const Args& args) {
  const Job job = load(args);
  const auto report = run_job(job);
  const auto ran = std::count_if(report.begin(), report.end(), [](const auto& s) { return s.status == "ran"; });
  spdlog::info("{} stages: {} ran, {} cached; output in {}", report.size(), ran, report.size() - ran,
               job.output.string());
  for (const auto& s : report)
    if (s.summary.is_object() && s.summary.contains("flagged") && !s.summary["flagged"].empty())
      spdlog::warn("{}: {} observations flagged and excluded: {}", s.id, s.summary["flagged"].size(),
                   s.summary["flagged"].dump());
  return kExitOk;
}

int cmd_eval(const Args& args) {
  if (args.positional[0] != "poses")
    throw InputError("olt eval", "unknown evaluation '" + args.positional[0] + "' (expected: poses)");
  const std::string estimate_file = args.positional[1], truth_file = args.positional[2];
  const std::string max_dt_text = args.value("--max-dt", "0.02");
  char* end = nullptr;
  const double max_dt = std::strtod(max_dt_text.c_str(), &end);
  if (*end != '\0' || !(max_dt > 0))
    throw InputError("--max-dt", "expected a positive number of seconds, got '" + max_dt_text + "'");
  const Trajectory estimate = parse_tum_trajectory(estimate_file, read_file(estimate_file));
  const Trajectory truth = parse_tum_trajectory(truth_file, read_file(truth_file));
  const TrajectoryErrors e = trajectory_errors(estimate, truth, max_dt);
  if (e.matched < 2) throw InputError(estimate_file, "fewer than 2 poses match the ground truth within --max-dt");
  if (args.has("--plot"))
    write_file_atomic(args.value("--plot", ""),
                      encode_png(plot_trajectories(estimate, truth, e.T_groundtruth_estimate, 800)));
  auto stats = [](const ErrorStats& s) {
    return nlohmann::json{{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"max", s.max}, {"count", s.count}};
  };
  if (args.has("--json")) {
    const nlohmann::json out = {{"matched", e.matched},
                                {"estimate_poses", estimate.size()},
                                {"ate_m", stats(e.ate_m)},
                                {"rpe_frame_m", stats(e.rpe_frame_m)},
                                {"rpe_frame_deg", stats(e.rpe_frame_deg)},
                                {"rpe_second_m", stats(e.rpe_second_m)},
                                {"rpe_second_deg", stats(e.rpe_second_deg)}};
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("matched poses          %d of %zu\n", e.matched, estimate.size());
    std::printf("ATE RMSE               %.4f m (median %.4f, max %.4f)\n", e.ate_m.rmse, e.ate_m.median, e.ate_m.max);
    std::printf("RPE per frame  RMSE    %.4f m  %.3f deg\n", e.rpe_frame_m.rmse, e.rpe_frame_deg.rmse);
    std::printf("RPE per second RMSE    %.4f m  %.3f deg\n", e.rpe_second_m.rmse, e.rpe_second_deg.rmse);
  }
  return kExitOk;
}

int cmd_version(const Args&) {
  std::printf("olt %s\n", OLT_VERSION);
  return kExitOk;
}

int cmd_help(const Args& args);

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {"run", "olt run JOB", "run the job graph; only stages whose inputs changed run", {}, 1, cmd_run},
      {"validate", "olt validate JOB", "check the job and its inputs without running anything", {}, 1, cmd_validate},
      {"plan", "olt plan JOB [--json]", "say which stages would run, and why", {"--json"}, 1, cmd_plan},
      {"eval",
       "olt eval poses ESTIMATE GROUNDTRUTH [--json] [--max-dt=S] [--plot=PNG]",
       "trajectory error (ATE, RPE per frame and per second) of a TUM trajectory against ground truth",
       {"--json", "--max-dt=", "--plot="},
       3,
       cmd_eval},
      {"version", "olt version", "print the version", {}, 0, cmd_version},
      {"help", "olt help [COMMAND]", "list commands and stage kinds, or explain one command", {}, 0, cmd_help},
  };
  return table;
}

const Command* find_command(const std::string& name) {
  for (const auto& c : commands())
    if (name == c.name) return &c;
  return nullptr;
}

int cmd_help(const Args& args) {
  if (!args.positional.empty()) {
    if (const Command* c = find_command(args.positional[0])) {
      std::printf("usage: %s\n  %s\n", c->usage, c->summary);
      return kExitOk;
    }
  }
  std::printf("olt: turns RGB-D recordings into densely labeled datasets\n\ncommands:\n");
  for (const auto& c : commands()) std::printf("  %-24s %s\n", c.usage, c.summary);
  std::printf("\nstage kinds:");
  for (const auto& k : stage_kinds()) std::printf(" %s", k.spec.name.c_str());
  std::printf("\n\nexit codes: 0 success, 1 a stage failed, 2 invalid job or input (nothing ran)\n");
  return kExitOk;
}

}  // namespace

int run_cli(const std::vector<std::string>& argv) {
  auto logger = spdlog::stderr_color_mt("olt");
  logger->set_pattern("%H:%M:%S %^%l%$ %v");
  spdlog::set_default_logger(logger);

  if (argv.empty()) {
    cmd_help({});
    return kExitInvalidInput;
  }
  const Command* command = find_command(argv[0]);
  if (!command) {
    std::fprintf(stderr, "olt: unknown command '%s' (see olt help)\n", argv[0].c_str());
    return kExitInvalidInput;
  }
  Args args;
  for (size_t i = 1; i < argv.size(); ++i) {
    if (argv[i] == "--help" || argv[i] == "-h") {
      std::printf("usage: %s\n  %s\n", command->usage, command->summary);
      return kExitOk;
    }
    if (argv[i].rfind("--", 0) == 0) {
      const auto equals = argv[i].find('=');
      const std::string name = argv[i].substr(0, equals);
      const bool takes_value =
          std::find(command->flags.begin(), command->flags.end(), name + "=") != command->flags.end();
      const bool plain = std::find(command->flags.begin(), command->flags.end(), name) != command->flags.end();
      std::string value;
      if (takes_value && equals != std::string::npos) {
        value = argv[i].substr(equals + 1);
      } else if (takes_value && i + 1 < argv.size()) {
        value = argv[++i];
      } else if (!plain || equals != std::string::npos) {
        std::fprintf(stderr, "olt %s: unknown option or missing value '%s'\nusage: %s\n", command->name,
                     argv[i].c_str(), command->usage);
        return kExitInvalidInput;
      }
      args.flags[name] = value;
    } else {
      args.positional.push_back(argv[i]);
    }
  }
  const bool optional_args = std::string(command->name) == "help";
  if (!optional_args && args.positional.size() != command->positional) {
    std::fprintf(stderr, "olt %s: expected %zu argument(s)\nusage: %s\n", command->name, command->positional,
                 command->usage);
    return kExitInvalidInput;
  }
  try {
    return command->run(args);
  } catch (const InputError& e) {
    for (const auto& d : e.diagnostics()) std::fprintf(stderr, "%s\n", d.str().c_str());
    std::fprintf(stderr, "olt %s: invalid input (%zu problem%s)\n", command->name, e.diagnostics().size(),
                 e.diagnostics().size() == 1 ? "" : "s");
    return kExitInvalidInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "olt %s: %s\n", command->name, e.what());
    return kExitStageFailed;
  }
}

}  // namespace olt
