// Progress lines, with the clock and the output injected: what they say, and how often, on a
// terminal (a live line) and not (a log line every 5 s).
#include "olt/core/progress.h"

#include <catch2/catch.hpp>
#include <vector>

TEST_CASE("progress text: done/total, rate and time left") {
  CHECK(olt::Progress::describe(120, 250, "frames", 2.5) == "120/250 frames, 48/s, 3 s left");
  CHECK(olt::Progress::describe(3, 10, "", 2.0) == "3/10, 1.5/s, 5 s left");
  CHECK(olt::Progress::describe(10, 10000, "frames", 100.0) == "10/10000 frames, 0.1/s, 27 h 45 min left");
  CHECK(olt::Progress::describe(250, 250, "frames", 5.0) == "250/250 frames, 50/s");
  CHECK(olt::Progress::describe(0, 250, "frames", 0.0) == "0/250 frames");
}

TEST_CASE("progress: a line every 5 s in a log, a live line at most every 0.2 s on a terminal") {
  for (const bool terminal : {false, true}) {
    double now = 100;
    std::vector<std::string> lines;
    {
      olt::Progress progress(
          "labels: frames", 100, [&] { return now; }, [&](const std::string& line) { lines.push_back(line); },
          terminal);
      for (int i = 0; i < 100; ++i) {
        now += 0.125;  // 8 frames a second, 12.5 s in all (exact in binary)
        progress.advance();
      }
    }
    INFO("terminal " << terminal);
    if (!terminal) {
      REQUIRE(lines.size() == 2);  // at 5 s and 10 s
      CHECK(lines[0] == "labels: 40/100 frames, 8.0/s, 8 s left");
      CHECK(lines[1] == "labels: 80/100 frames, 8.0/s, 3 s left");
    } else {
      CHECK(lines.size() == 51);  // every other frame (0.25 s apart), and the clearing
      CHECK(lines[0].rfind("\r\033[K", 0) == 0);
      CHECK(lines.back() == "\r\033[K");  // cleared at the end
    }
  }
}
