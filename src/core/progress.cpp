#include "olt/core/progress.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace olt {
namespace {

constexpr double kTerminalEvery = 0.2, kLogEvery = 5.0;  // seconds between reports

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string duration(double seconds) {
  char text[32];
  if (seconds < 60)
    std::snprintf(text, sizeof(text), "%.0f s", std::ceil(seconds));
  else if (seconds < 3600)
    std::snprintf(text, sizeof(text), "%d min %02d s", static_cast<int>(seconds) / 60, static_cast<int>(seconds) % 60);
  else
    std::snprintf(text, sizeof(text), "%d h %02d min", static_cast<int>(seconds) / 3600,
                  static_cast<int>(seconds) / 60 % 60);
  return text;
}

}  // namespace

Progress::Progress(std::string what, size_t total)
    : Progress(
          std::move(what), total, steady_seconds,
          [](const std::string& line) {
            if (!line.empty() && line[0] == '\r')
              std::fputs(line.c_str(), stderr);
            else
              spdlog::info("{}", line);
          },
          ::isatty(2) == 1) {
  enabled_ = spdlog::default_logger()->should_log(spdlog::level::info);
}

Progress::Progress(std::string what, size_t total, Clock clock, Sink sink, bool terminal)
    : total_(total), clock_(std::move(clock)), sink_(std::move(sink)), terminal_(terminal), enabled_(true) {
  const auto colon = what.rfind(": ");
  name_ = colon == std::string::npos ? what : what.substr(0, colon);
  unit_ = colon == std::string::npos ? "" : what.substr(colon + 2);
  start_ = last_ = clock_();
}

Progress::~Progress() {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (enabled_ && terminal_ && shown_) sink_("\r\033[K");  // the live line cleared: the log goes on below
}

std::string Progress::describe(size_t done, size_t total, const std::string& unit, double seconds) {
  std::string text = std::to_string(done) + "/" + std::to_string(total) + (unit.empty() ? "" : " " + unit);
  if (seconds > 0 && done > 0) {
    const double rate = done / seconds;
    char figure[32];
    std::snprintf(figure, sizeof(figure), rate >= 10 ? ", %.0f/s" : ", %.1f/s", rate);
    text += figure;
    if (done < total) text += ", " + duration((total - done) / rate) + " left";
  }
  return text;
}

void Progress::advance(size_t n) {
  const std::lock_guard<std::mutex> lock(mutex_);
  done_ += n;
  if (!enabled_) return;
  const double now = clock_();
  if (now - last_ < (terminal_ ? kTerminalEvery : kLogEvery)) return;
  last_ = now;
  report(false);
}

void Progress::report(bool) {
  const std::string line = name_ + ": " + describe(done_, total_, unit_, clock_() - start_);
  sink_(terminal_ ? "\r\033[K" + line : line);
  shown_ = true;
}

}  // namespace olt
