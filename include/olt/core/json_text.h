#pragma once
// Documents too big to hold as one JSON value (a manifest of 80,000 files, the records of 10,000
// frames) written a member at a time, byte-identical to nlohmann::json's dump(1) of the whole, and
// read an element at a time.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace olt {

/// Appends `text` as nlohmann::json writes a string: quoted and escaped (for documents assembled by
/// hand). Printable ASCII without quotes or backslashes (paths, ids, digests: nearly every string)
/// is quoted as it is; anything else goes through nlohmann.
inline void append_json_string(std::string& to, std::string_view text) {
  for (const char c : text)
    if (c < 0x20 || c > 0x7e || c == '"' || c == '\\') {
      to += nlohmann::json(std::string(text)).dump();
      return;
    }
  to += '"';
  to += text;
  to += '"';
}

/// `text` as nlohmann::json writes a string (append_json_string).
inline std::string json_string(std::string_view text) {
  std::string quoted;
  quoted.reserve(text.size() + 2);
  append_json_string(quoted, text);
  return quoted;
}

/// Appends `value` as dump(1) writes it `depth` levels deep in a document: every line after its first
/// indented by `depth` more spaces.
void append_nested(std::string& text, const nlohmann::json& value, int depth);

/// Appends, as dump(1) writes it `depth` levels deep, an array of `count` elements made one at a time
/// by `element(i)`; after each, `drain` (when given) may take the text so far away (to a file).
void append_array(std::string& text, size_t count, const std::function<nlohmann::json(size_t)>& element, int depth,
                  const std::function<void(std::string&)>& drain = nullptr);

/// Calls `each` with every object (or plain value) found `depth` levels deep in the JSON `text`,
/// parsing one at a time: the document around them is never held whole. Throws nlohmann's parse
/// errors.
void for_each_at(const std::string& text, int depth, const std::function<void(const nlohmann::json&)>& each);

}  // namespace olt
