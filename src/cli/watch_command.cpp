// `olt watch JOB [--listen=ADDR] [--poll=S] [--settle=S] [--poll-only] [--image-memory=MB]
// [--gc-idle=S | --no-gc]`: the daemon of the annotation loop.
#include <cstdlib>
#include <optional>

#include "args.h"
#include "olt/core/error.h"
#include "olt/watch/watch.h"
#include "stop_signals.h"

namespace olt {
namespace {

double seconds_flag(const Args& args, const std::string& flag, double fallback) {
  if (!args.has(flag)) return fallback;
  const std::string text = args.value(flag, "");
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(value > 0) || value > 3600)
    throw InputError(flag, "expected a number of seconds in (0, 3600], got '" + text + "'");
  return value;
}

// --image-memory=MB: a whole number of megabytes, 0 to 1,000,000.
std::optional<size_t> megabytes_flag(const Args& args, const std::string& flag) {
  if (!args.has(flag)) return std::nullopt;
  const std::string text = args.value(flag, "");
  if (text.empty() || text.size() > 7 || text.find_first_not_of("0123456789") != std::string::npos ||
      std::stoul(text) > 1000000)
    throw InputError(flag, "expected a whole number of megabytes from 0 to 1000000, got '" + text + "'");
  return std::stoul(text);
}

}  // namespace

int cmd_watch(const Args& args) {
  WatchConfig config;
  config.job = args.positional.at(0);
  config.listen = args.value("--listen", "");
  config.poll_interval_s = seconds_flag(args, "--poll", config.poll_interval_s);
  config.settle_s = seconds_flag(args, "--settle", config.settle_s);
  config.image_memory_mb = megabytes_flag(args, "--image-memory");
  config.events = !args.has("--poll-only");
  if (args.has("--no-gc") && args.has("--gc-idle"))
    throw InputError("--gc-idle", "--no-gc says never to collect: give one of the two");
  config.gc_idle_s = args.has("--no-gc") ? 0 : seconds_flag(args, "--gc-idle", config.gc_idle_s);
  // SIGINT and SIGTERM only set a flag: a cycle under way stops at its next frame or stage, its
  // output left as the last cycle published it, and the daemon returns (a stop is how it ends: 0).
  return watch_job(config, stop_on_signals());
}

}  // namespace olt
