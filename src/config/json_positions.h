#pragma once
// Where a JSON pointer's key and value stand in a JSON text, found by walking the text to it.
// A JSON document's positions are needed only for its errors: walking to the few an error names
// costs nothing on a good file, where a table of every value's position cost more than parsing it.
#include <string>
#include <string_view>

#include "olt/config/document.h"

namespace olt {

struct PointerPositions {
  Position value;  ///< of the deepest value on the pointer's path the text has; 0 = none
  Position key;    ///< of the pointer's last key, if the text has it (objects only); else 0
};

/// `text` must be valid JSON (it was parsed already). A pointer's tokens are matched against keys
/// as the text's escapes decode them, so "caf\u00e9" is found as "café".
PointerPositions json_positions(std::string_view text, const std::string& pointer);

}  // namespace olt
