#pragma once
// Line-by-line reading of whitespace-separated text files (TUM lists and trajectories, laser scans,
// odometry), with errors at FILE:LINE.
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "olt/core/error.h"

namespace olt {

/// Calls `handle(line_number, fields)` for each non-empty line not starting with '#'.
template <class Handle>
void for_each_line(const std::string& text, Handle handle) {
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    std::istringstream words(line);
    std::vector<std::string> fields;
    for (std::string w; words >> w;) fields.push_back(w);
    handle(number, fields);
  }
}

inline double parse_number(const std::string& file, int line, const std::string& word, const std::string& what) {
  char* end = nullptr;
  const double value = std::strtod(word.c_str(), &end);
  if (end == word.c_str() || *end != '\0' || !std::isfinite(value))
    throw InputError({{file, line, 1, "expected a finite number for " + what + ", got '" + word + "'"}});
  return value;
}

}  // namespace olt
