#pragma once
// printf-style formatting into a string of whatever length it takes: a number such as 1e308 printed
// with %.9f is 320 characters, and a fixed buffer would cut the line it is part of.
#include <string>

namespace olt {

std::string format_text(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace olt
