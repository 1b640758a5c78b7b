#pragma once
// Progress of a long loop (frames labeled, keyframes registered): done/total, rate and time left,
// so a person can tell work from a hang. On a terminal one live line, redrawn at most five times a
// second; otherwise (a log file, Slurm) a line every 5 s. Nothing under --quiet (the log level
// above info). Safe to advance from many threads.
#include <chrono>
#include <functional>
#include <mutex>
#include <string>

namespace olt {

class Progress {
 public:
  using Clock = std::function<double()>;                 ///< seconds, monotonic
  using Sink = std::function<void(const std::string&)>;  ///< one line (terminal: "\r"-prefixed, no newline)

  /// `what` names the work and its unit ("labels: frames"); reports go to stderr (a terminal or not,
  /// as it is) through the log's level.
  Progress(std::string what, size_t total);
  /// For tests: the clock, where lines go, and whether it is a terminal.
  Progress(std::string what, size_t total, Clock clock, Sink sink, bool terminal);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(size_t n = 1);

  /// "120/250 frames, 48.1/s, 3 s left" (the line's text, without the name).
  static std::string describe(size_t done, size_t total, const std::string& unit, double seconds);

 private:
  void report(bool final);

  std::string name_, unit_;
  size_t total_, done_ = 0;
  Clock clock_;
  Sink sink_;
  bool terminal_, enabled_;
  double start_, last_ = 0;
  bool shown_ = false;
  std::mutex mutex_;
};

}  // namespace olt
