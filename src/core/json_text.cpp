#include "olt/core/json_text.h"

namespace olt {

void append_nested(std::string& text, const nlohmann::json& value, int depth) {
  const std::string indent(static_cast<size_t>(depth), ' ');
  for (const char c : value.dump(1)) {
    text += c;
    if (c == '\n') text += indent;
  }
}

}  // namespace olt
