#include "json_positions.h"

#include <algorithm>
#include <cstdint>

namespace olt {
namespace {

void append_utf8(std::string& out, uint32_t code) {
  if (code < 0x80) {
    out += static_cast<char>(code);
  } else if (code < 0x800) {
    out += static_cast<char>(0xC0 | (code >> 6));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else if (code < 0x10000) {
    out += static_cast<char>(0xE0 | (code >> 12));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (code >> 18));
    out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  }
}

// A cursor over valid JSON text: it skips what it does not need and decodes only keys.
class Walker {
 public:
  explicit Walker(std::string_view text) : t_(text) {}

  size_t at() const { return i_; }
  char next() const { return i_ < t_.size() ? t_[i_] : '\0'; }
  void step() { ++i_; }
  void seek(size_t at) { i_ = at; }

  void space() {
    while (i_ < t_.size() && (t_[i_] == ' ' || t_[i_] == '\t' || t_[i_] == '\n' || t_[i_] == '\r')) ++i_;
  }

  /// The string that starts here, decoded, the cursor after its closing quote.
  std::string string() {
    std::string out;
    ++i_;  // the opening quote
    while (i_ < t_.size() && t_[i_] != '"') {
      if (t_[i_] != '\\') {
        out += t_[i_++];
        continue;
      }
      const char escaped = i_ + 1 < t_.size() ? t_[i_ + 1] : '\0';
      i_ += 2;
      switch (escaped) {
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'n':
          out += '\n';
          break;
        case 'r':
          out += '\r';
          break;
        case 't':
          out += '\t';
          break;
        case 'u': {
          uint32_t code = hex4();
          if (code >= 0xD800 && code < 0xDC00 && next() == '\\') {  // a surrogate pair
            i_ += 2;
            code = 0x10000 + ((code - 0xD800) << 10) + (hex4() - 0xDC00);
          }
          append_utf8(out, code);
          break;
        }
        default:
          out += escaped;  // " \ /
      }
    }
    ++i_;  // the closing quote
    return out;
  }

  /// Past the value that starts here: a scalar, a string, an object or an array.
  void skip_value() {
    int depth = 0;
    do {
      const char c = next();
      if (c == '"') {
        skip_string();
        continue;
      }
      if (c == '{' || c == '[') {
        ++depth;
      } else if (c == '}' || c == ']') {
        --depth;
      } else if (depth == 0) {  // a number or a literal
        while (i_ < t_.size() && std::string_view(",]} \t\r\n").find(t_[i_]) == std::string_view::npos) ++i_;
        return;
      }
      ++i_;
    } while (depth > 0 && i_ < t_.size());
  }

 private:
  uint32_t hex4() {
    uint32_t code = 0;
    for (int k = 0; k < 4 && i_ < t_.size(); ++k, ++i_) {
      const char c = t_[i_];
      code = code * 16 + static_cast<uint32_t>(c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10);
    }
    return code;
  }

  void skip_string() {
    for (++i_; i_ < t_.size() && t_[i_] != '"'; ++i_)
      if (t_[i_] == '\\') ++i_;
    ++i_;
  }

  std::string_view t_;
  size_t i_ = 0;
};

std::string unescape_token(const std::string& token) {
  std::string out;
  for (size_t k = 0; k < token.size(); ++k) {
    if (token[k] == '~' && k + 1 < token.size() && (token[k + 1] == '0' || token[k + 1] == '1')) {
      out += token[k + 1] == '0' ? '~' : '/';
      ++k;
    } else {
      out += token[k];
    }
  }
  return out;
}

// Into the member `key` of the object at the cursor: the cursor at its value, the key's offset
// returned; npos where the object has no such member.
size_t enter_member(Walker& w, const std::string& key) {
  w.step();  // {
  w.space();
  while (w.next() == '"') {
    const size_t key_at = w.at();
    const bool found = w.string() == key;
    w.space();
    w.step();  // :
    w.space();
    if (found) return key_at;
    w.skip_value();
    w.space();
    if (w.next() == ',') w.step();
    w.space();
  }
  return std::string_view::npos;
}

// The element an array index names, as JSON pointers write it (no sign, no leading zero); npos
// for a token that is not one.
size_t array_index(const std::string& token) {
  if (token.empty() || token.size() > 18 || (token.size() > 1 && token[0] == '0') ||
      !std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::string::npos;
  return std::stoull(token);
}

}  // namespace

Position position_in(std::string_view text, size_t offset) {
  offset = std::min(offset, text.size());
  const std::string_view before = text.substr(0, offset);
  const size_t line_start = before.rfind('\n') == std::string_view::npos ? 0 : before.rfind('\n') + 1;
  return {1 + static_cast<int>(std::count(before.begin(), before.end(), '\n')),
          1 + static_cast<int>(offset - line_start)};
}

Position JsonPositions::at(size_t offset) const {
  if (line_starts_.empty()) {
    line_starts_.push_back(0);
    for (size_t i = text_.find('\n'); i != std::string::npos; i = text_.find('\n', i + 1))
      line_starts_.push_back(i + 1);
  }
  offset = std::min(offset, text_.size());
  const auto line = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset) - 1;
  return {1 + static_cast<int>(line - line_starts_.begin()), 1 + static_cast<int>(offset - *line)};
}

const std::vector<size_t>& JsonPositions::elements(size_t array) const {
  const auto known = elements_.find(array);
  if (known != elements_.end()) return known->second;
  std::vector<size_t>& found = elements_[array];
  Walker w(text_);
  w.seek(array + 1);  // past [
  w.space();
  while (w.next() != ']' && w.next() != '\0') {
    found.push_back(w.at());
    w.skip_value();
    w.space();
    if (w.next() == ',') w.step();
    w.space();
  }
  return found;
}

PointerPositions JsonPositions::find(const std::string& pointer) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  // A byte order mark, which the parser skips too and an editor does not show as a column.
  const size_t start = text_.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  Walker w(text_);
  w.seek(start);
  w.space();
  PointerPositions out;
  const auto at_offset = [&](size_t offset) {
    Position p = at(offset);
    if (p.line == 1) p.column -= static_cast<int>(start);
    return p;
  };
  out.value = at_offset(w.at());
  size_t from = 0;
  while (from < pointer.size()) {  // each "/token"
    const size_t end = std::min(pointer.find('/', from + 1), pointer.size());
    const std::string token = unescape_token(pointer.substr(from + 1, end - from - 1));
    if (w.next() == '{') {
      const size_t key_at = enter_member(w, token);
      if (key_at == std::string_view::npos) return out;
      if (end == pointer.size()) out.key = at_offset(key_at);
    } else if (w.next() == '[') {
      const std::vector<size_t>& items = elements(w.at());
      const size_t index = array_index(token);
      if (index >= items.size()) return out;
      w.seek(items[index]);
    } else {
      return out;
    }
    out.value = at_offset(w.at());
    from = end;
  }
  return out;
}

}  // namespace olt
