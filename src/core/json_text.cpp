#include "olt/core/json_text.h"

namespace olt {

void append_nested(std::string& text, const nlohmann::json& value, int depth) {
  const std::string indent(static_cast<size_t>(depth), ' ');
  for (const char c : value.dump(1)) {
    text += c;
    if (c == '\n') text += indent;
  }
}

void append_array(std::string& text, size_t count, const std::function<nlohmann::json(size_t)>& element, int depth,
                  const std::function<void(std::string&)>& drain) {
  if (count == 0) {
    text += "[]";
    return;
  }
  const std::string inner = "\n" + std::string(static_cast<size_t>(depth + 1), ' ');
  text += "[";
  for (size_t i = 0; i < count; ++i) {
    text += i == 0 ? inner : "," + inner;
    append_nested(text, element(i), depth + 1);
    if (drain) drain(text);
  }
  text += "\n" + std::string(static_cast<size_t>(depth), ' ') + "]";
}

void for_each_at(const std::string& text, int depth, const std::function<void(const nlohmann::json&)>& each) {
  const nlohmann::json rest =
      nlohmann::json::parse(text, [&](int d, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        if (d != depth ||
            (event != nlohmann::json::parse_event_t::object_end && event != nlohmann::json::parse_event_t::value))
          return true;
        each(parsed);
        return false;  // dropped from the document once seen
      });
  (void)rest;  // the document without those elements
}

}  // namespace olt
