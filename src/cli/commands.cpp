#include "olt/cli/commands.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <optional>

#include "args.h"
#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/core/threads.h"
#include "olt/eval/trajectory_error.h"
#include "olt/formats/tum.h"
#include "olt/job/job.h"
#include "olt/runtime/runner.h"
#include "olt/runtime/shard.h"
#include "olt/runtime/units.h"
#include "olt/stages/stage.h"
#include "olt/watch/watch.h"
#include "stop_signals.h"

#ifndef OLT_VERSION
#define OLT_VERSION "dev"
#endif

namespace olt {
namespace {

struct Command {
  const char* name;
  const char* usage;
  const char* summary;
  std::vector<std::string> flags;  ///< accepted flags besides --help; "--name=" takes a value
  int positional;                  ///< number of positional arguments; -1: the command checks
  std::function<int(const Args&)> run;
};

Job load(const Args& args) { return load_runnable_job(args.positional.at(0)); }

int cmd_validate(const Args& args) {
  const Job job = load(args);
  std::printf("%s: valid (%zu stages)\n", job.file.c_str(), job.stages.size());
  return kExitOk;
}

int cmd_plan(const Args& args) {
  const Job job = load(args);
  if (args.has("--units")) {
    int shards = 1;
    if (args.has("--shards")) {
      shards = parse_shard("0/" + args.value("--shards", ""), "--shards").count;
    } else if (const auto shard = shard_from_environment(std::getenv)) {
      shards = shard->count;
    }
    std::printf("%s\n", plan_units(job, shards).dump(args.has("--json") ? 2 : -1).c_str());
    return kExitOk;
  }
  const auto plan = plan_job(job);
  if (args.has("--json")) {
    nlohmann::json stages = nlohmann::json::array();
    for (const auto& s : plan) {
      nlohmann::json j = {{"id", s.id}, {"kind", s.kind}, {"status", s.status}, {"reason", s.reason}};
      if (!s.detail.is_null()) j["detail"] = s.detail;
      stages.push_back(j);
    }
    std::printf("%s\n", nlohmann::json{{"stages", stages}}.dump(2).c_str());
  } else {
    for (const auto& s : plan) {
      std::printf("%-16s %-12s %-7s %s\n", s.id.c_str(), s.kind.c_str(), s.status.c_str(), s.reason.c_str());
      if (s.detail.is_object() && s.detail.contains("text"))
        std::printf("%-37s %s\n", "", s.detail["text"].get<std::string>().c_str());
    }
  }
  return kExitOk;
}

// "3 flagged and left out: rgbd 000012 (no overlap with the scene), ... (all in its summary.json)"
std::string flagged_line(const nlohmann::json& flagged) {
  std::string line = std::to_string(flagged.size()) + " flagged and left out: ";
  const size_t shown = std::min<size_t>(flagged.size(), 5);
  for (size_t i = 0; i < shown; ++i) {
    const nlohmann::json& f = flagged[i];
    std::string what =
        f.contains("scan") ? "scan " + f["scan"].dump() : f.value("sensor", "") + " " + f.value("observation", "");
    line += (i ? ", " : "") + what + " (" + f.value("flag", "") + ")";
  }
  if (flagged.size() > shown)
    line += ", and " + std::to_string(flagged.size() - shown) + " more (the report lists all)";
  return line;
}

void log_report(const std::vector<StageStatus>& report, const std::string& where) {
  const auto count = [&](const char* status) {
    return std::count_if(report.begin(), report.end(), [&](const auto& s) { return s.status == status; });
  };
  spdlog::info("{} stages: {} ran, {} cached{}; {}", report.size(), count("ran"), count("cached"),
               count("skipped") ? ", " + std::to_string(count("skipped")) + " left to other shards or the merge" : "",
               where);
  for (const auto& s : report) {
    if (!s.summary.is_object()) continue;
    if (s.summary.contains("flagged") && s.summary["flagged"].is_array() && !s.summary["flagged"].empty())
      spdlog::warn("{}: {}", s.id, flagged_line(s.summary["flagged"]));
    // The stages' warnings again at the end, where they are read (a cached stage's too).
    if (s.summary.contains("warnings"))
      for (const auto& w : s.summary["warnings"])
        spdlog::warn("{}: {}", s.id, w.is_string() ? w.get<std::string>() : w.dump());
  }
}

// Where the output is, and the report page when the job makes one.
std::string output_line(const Job& job) {
  std::string line = "output in " + job.output.string();
  for (const auto& stage : job.stages)
    if (stage.kind == "report") line += "; report: " + (job.output / stage.id / "index.html").string();
  return line;
}

// A run stopped by a signal, said, then ended by that signal (as a shell or Slurm expects).
[[noreturn]] void stopped(const RunStopped& e, const std::string& output) {
  const int number = stop_signal();  // set before the flag: the stop's
  spdlog::error("{}: {}; {}; what the run finished is in the cache for the next run to find", signal_name(number),
                e.what(), output);
  end_by_signal(number);
}

int cmd_run(const Args& args) {
  const Job job = load(args);
  const auto shard = resolve_shard(args.value("--shard", ""), std::getenv);
  RunOptions options;
  options.shard = shard;
  options.stop = &stop_on_signals();
  std::vector<StageStatus> report;
  try {
    report = run_job(job, options);
  } catch (const RunStopped& e) {
    stopped(e, shard ? "the shard is not recorded as finished" : "nothing published, the output is as it was");
  }
  log_report(report,
             shard ? "shard " + shard->str() + " finished; `olt merge` assembles the output" : output_line(job));
  return kExitOk;
}

int cmd_merge(const Args& args) {
  const Job job = load(args);
  std::vector<StageStatus> report;
  try {
    report = merge_job(job, {}, &stop_on_signals());
  } catch (const RunStopped& e) {
    stopped(e, "nothing published, the output is as it was");
  }
  log_report(report, output_line(job));
  return kExitOk;
}

int cmd_version(const Args&) {
  std::printf("olt %s\n", OLT_VERSION);
  return kExitOk;
}

int cmd_help(const Args& args);

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {"run",
       "olt run JOB [--shard=i/N]",
       "run the job graph; only stages whose inputs changed run; --shard (or a Slurm array's or Kubernetes "
       "Indexed Job's environment) runs one shard's units into the cache, for olt merge",
       {"--shard="},
       1,
       cmd_run},
      {"merge",
       "olt merge JOB",
       "check that every shard of the job finished, then assemble and publish the output (exit 3 if not)",
       {},
       1,
       cmd_merge},
      {"validate", "olt validate JOB", "check the job and its inputs without running anything", {}, 1, cmd_validate},
      {"plan",
       "olt plan JOB [--json] [--units [--shards=N]]",
       "say which stages would run, and why; --units lists the work units of a sharded run",
       {"--json", "--units", "--shards="},
       1,
       cmd_plan},
      {"watch",
       "olt watch JOB [--listen=[HOST:]PORT] [--poll=S] [--settle=S] [--poll-only] [--image-memory=MB] "
       "[--gc-idle=S | --no-gc]",
       "run the job, then again after each settled edit of its files (boxes, job, trajectories); "
       "--listen serves /healthz, /status and /metrics (loopback unless HOST says otherwise); "
       "--poll-only does not listen to the system's reports of changes (inotify), only polls; "
       "--image-memory keeps that much of decoded images and labeled frames between cycles (an eighth of "
       "the memory the process may use, 512 (at most a quarter) to 4096; 0: none); "
       "once idle --gc-idle seconds (10) after a run that stored something, removes from the cache what no "
       "job's last run uses, as olt cache gc (--no-gc: never)",
       {"--listen=", "--poll=", "--settle=", "--poll-only", "--image-memory=", "--gc-idle=", "--no-gc"},
       1,
       cmd_watch},
      {"eval",
       "olt eval poses ESTIMATE GROUNDTRUTH [--json] [--max-dt=S] [--interpolate] [--plot=PNG] | "
       "olt eval labels A B [--json] [--worst=N]",
       "poses: trajectory error of a TUM trajectory against ground truth (ATE after aligning the positions, "
       "ATE rotation after aligning the rotations, RPE per frame and per second); --interpolate takes the "
       "ground truth between its samples instead of the nearest one. labels: agreement of two labelings of "
       "one recording (two olt run outputs, or two folders of class-id PNGs): frames compared, per-class IoU "
       "matched by class name, mean IoU, pixel agreement, and the N worst frames (default 5)",
       {"--json", "--max-dt=", "--interpolate", "--plot=", "--worst="},
       3,
       cmd_eval},
      {"boxes",
       "olt boxes convert --from=FORMAT --to=FORMAT IN OUT | olt boxes corners FILE [--format=FORMAT]",
       "convert box files between annotation tools, or print each box's eight corners",
       {"--from=", "--to=", "--format="},
       -1,
       cmd_boxes},
      {"cache",
       "olt cache verify JOB | olt cache gc JOB",
       "verify: re-hash every cache entry against its digests (exit 1 if any is damaged); gc: remove the "
       "entries no job's last run references, and leftovers of killed runs",
       {},
       2,
       cmd_cache},
      {"version", "olt version", "print the version", {}, 0, cmd_version},
      {"help",
       "olt help [COMMAND | KIND]",
       "list commands and stage kinds, or explain one command or stage kind's parameters",
       {},
       -1,
       cmd_help},
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
    const std::string& topic = args.positional[0];
    if (const Command* c = find_command(topic)) {
      std::printf("usage: %s\n  %s\n", c->usage, c->summary);
      return kExitOk;
    }
    if (print_kind_help(topic)) return kExitOk;
    std::vector<std::string> topics;
    for (const auto& c : commands()) topics.push_back(c.name);
    for (const auto& kind : stage_kinds()) topics.push_back(kind.spec.name);
    const std::string guess = did_you_mean(topic, topics);
    std::fprintf(stderr, "olt help: '%s' is neither a command nor a stage kind%s (see olt help)\n", topic.c_str(),
                 guess.empty() ? "" : ("; did you mean '" + guess + "'?").c_str());
    return kExitInvalidInput;
  }
  std::printf("olt: turns RGB-D recordings into densely labeled datasets\n\ncommands:\n");
  for (const auto& c : commands()) {
    if (std::strlen(c.usage) <= 24)
      std::printf("  %-24s %s\n", c.usage, c.summary);
    else
      std::printf("  %s\n  %-24s %s\n", c.usage, "", c.summary);
  }
  std::printf("\nstage kinds:");
  for (const auto& k : stage_kinds()) std::printf(" %s", k.spec.name.c_str());
  std::printf(
      "\n\nexit codes: 0 success, 1 a stage failed, 2 invalid job or input (nothing ran), 3 olt merge: shards "
      "missing\n");
  return kExitOk;
}

// The command's arguments: flags it knows (--name, --name=value or --name value) and positionals.
// Prints the problem and returns nullopt on an unknown flag or a missing value; --help prints usage.
std::optional<Args> parse_args(const Command& command, const std::vector<std::string>& argv, int* exit_code) {
  Args args;
  for (size_t i = 1; i < argv.size(); ++i) {
    if (argv[i] == "--help" || argv[i] == "-h") {
      std::printf("usage: %s\n  %s\n", command.usage, command.summary);
      *exit_code = kExitOk;
      return std::nullopt;
    }
    if (argv[i].rfind("--", 0) != 0) {
      args.positional.push_back(argv[i]);
      continue;
    }
    const auto equals = argv[i].find('=');
    const std::string name = argv[i].substr(0, equals);
    const bool takes_value = std::find(command.flags.begin(), command.flags.end(), name + "=") != command.flags.end();
    const bool plain = std::find(command.flags.begin(), command.flags.end(), name) != command.flags.end();
    std::string value;
    if (takes_value && equals != std::string::npos) {
      value = argv[i].substr(equals + 1);
    } else if (takes_value && i + 1 < argv.size()) {
      value = argv[++i];
    } else if (!plain || equals != std::string::npos) {
      std::fprintf(stderr, "olt %s: unknown option or missing value '%s'\nusage: %s\n", command.name, argv[i].c_str(),
                   command.usage);
      *exit_code = kExitInvalidInput;
      return std::nullopt;
    }
    args.flags[name] = value;
  }
  if (command.positional >= 0 && args.positional.size() != static_cast<size_t>(command.positional)) {
    std::fprintf(stderr, "olt %s: expected %d argument(s)\nusage: %s\n", command.name, command.positional,
                 command.usage);
    *exit_code = kExitInvalidInput;
    return std::nullopt;
  }
  return args;
}

// Runs the command; what it throws becomes a message and the exit code of its kind.
int run_command(const Command& command, const Args& args) {
  try {
    return command.run(args);
  } catch (const InputError& e) {
    for (const auto& d : e.diagnostics()) std::fprintf(stderr, "%s\n", d.str().c_str());
    std::fprintf(stderr, "olt %s: invalid input (%zu problem%s)\n", command.name, e.diagnostics().size(),
                 e.diagnostics().size() == 1 ? "" : "s");
    return kExitInvalidInput;
  } catch (const ShardsIncomplete& e) {
    std::fprintf(stderr, "olt %s: %s\n", command.name, e.what());
    return kExitIncomplete;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "olt %s: %s\n", command.name, e.what());
    return kExitStageFailed;
  }
}

// The thread pool of the commands that compute (olt/core/threads.h); false, said, on a bad OLT_THREADS.
bool threads_configured() {
  try {
    const ThreadCount threads = configure_threads();
    spdlog::debug("threads: {} ({})", threads.threads, threads.why);
    return true;
  } catch (const InputError& e) {
    std::fprintf(stderr, "olt: %s\n", e.what());
    return false;
  }
}

}  // namespace

int run_cli(const std::vector<std::string>& given) {
  auto logger = spdlog::stderr_color_mt("olt");
  logger->set_pattern("%H:%M:%S %^%l%$ %v");
  spdlog::set_default_logger(logger);
  // -q/--quiet (warnings and errors only) and -v/--verbose (debug detail) go with any command,
  // anywhere on the line.
  std::vector<std::string> argv;
  for (const auto& word : given) {
    if (word == "-q" || word == "--quiet")
      logger->set_level(spdlog::level::warn);
    else if (word == "-v" || word == "--verbose")
      logger->set_level(spdlog::level::debug);
    else
      argv.push_back(word);
  }

  if (argv.empty()) {
    cmd_help({});
    return kExitInvalidInput;
  }
  if (argv[0] == "--help" || argv[0] == "-h") return cmd_help({});
  if (argv[0] == "--version" || argv[0] == "-V") return cmd_version({});
  const Command* command = find_command(argv[0]);
  if (!command) {
    std::vector<std::string> names;
    for (const auto& c : commands()) names.push_back(c.name);
    const std::string guess = did_you_mean(argv[0], names);
    std::fprintf(stderr, "olt: unknown command '%s'%s (see olt help)\n", argv[0].c_str(),
                 guess.empty() ? "" : ("; did you mean '" + guess + "'?").c_str());
    return kExitInvalidInput;
  }
  // Help and version work whatever OLT_THREADS says.
  const std::string name = command->name;
  if (name != "help" && name != "version" && !threads_configured()) return kExitInvalidInput;
  int exit_code = kExitOk;
  const std::optional<Args> args = parse_args(*command, argv, &exit_code);
  return args ? run_command(*command, *args) : exit_code;
}

}  // namespace olt
