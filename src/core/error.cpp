#include "olt/core/error.h"

#include <cstdint>

namespace olt {
namespace {

std::string join(const std::vector<Diagnostic>& diagnostics) {
  std::string text;
  for (const auto& d : diagnostics) {
    if (!text.empty()) text += '\n';
    text += d.str();
  }
  return text;
}

}  // namespace

std::string Diagnostic::str() const {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line) + ":" + std::to_string(column);
  return where + ": " + message;
}

InputError::InputError(std::vector<Diagnostic> diagnostics)
    : std::runtime_error(join(diagnostics)), diagnostics_(std::move(diagnostics)) {}

InputError::InputError(const std::string& file, const std::string& message)
    : InputError(std::vector<Diagnostic>{{file, 0, 0, message}}) {}

}  // namespace olt

namespace olt {

namespace {

size_t utf8_sequence(std::string_view text, size_t i) {
  const auto byte = static_cast<unsigned char>(text[i]);
  // The sequence length from the lead byte, and the smallest code point it may encode.
  const size_t length = byte < 0x80 ? 1 : (byte >> 5) == 0x6 ? 2 : (byte >> 4) == 0xE ? 3 : (byte >> 3) == 0x1E ? 4 : 0;
  bool valid = length > 0 && i + length <= text.size();
  uint32_t code = length == 1 ? byte : length == 2 ? byte & 0x1F : length == 3 ? byte & 0x0F : byte & 0x07;
  for (size_t k = 1; valid && k < length; ++k) {
    const auto next = static_cast<unsigned char>(text[i + k]);
    valid = (next & 0xC0) == 0x80;
    code = (code << 6) | (next & 0x3F);
  }
  static const uint32_t kSmallest[5] = {0, 0, 0x80, 0x800, 0x10000};
  if (valid && (code < kSmallest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF))) valid = false;
  return valid ? length : 0;
}

std::string hex_byte(unsigned char byte) {
  static const char* hex = "0123456789ABCDEF";
  return std::string("0x") + hex[byte >> 4] + hex[byte & 0xF];
}

}  // namespace

std::string invalid_utf8(std::string_view text) {
  for (size_t i = 0; i < text.size();) {
    const size_t length = utf8_sequence(text, i);
    if (length == 0) return "byte " + hex_byte(static_cast<unsigned char>(text[i])) + " at " + std::to_string(i + 1);
    i += length;
  }
  return "";
}

void check_utf8(const std::string& file, std::string_view text) {
  int line = 1, column = 1;
  for (size_t i = 0; i < text.size();) {
    const size_t length = utf8_sequence(text, i);
    if (length == 0)
      throw InputError(
          {{file, line, column,
            "invalid UTF-8 (byte " + hex_byte(static_cast<unsigned char>(text[i])) + "): text files must be UTF-8"}});
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
    i += length;
  }
}

}  // namespace olt
