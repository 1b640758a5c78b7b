#pragma once
// Where a JSON pointer's key and value stand in a JSON text, found by walking the text to it.
// A JSON document's positions are needed only for its errors: walking to the few an error names
// costs nothing on a good file, where a table of every value's position cost more than parsing it.
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "olt/config/document.h"

namespace olt {

struct PointerPositions {
  Position value;  ///< of the deepest value on the pointer's path the text has; 0 = none
  Position key;    ///< of the pointer's last key, if the text has it (objects only); else 0
};

/// One JSON text's positions. The text must be valid JSON (it was parsed already). A pointer's
/// tokens are matched against keys as the text's escapes decode them, so "caf\u00e9" is found as
/// "café". Thread-safe. What a walk learns of the text's lines and arrays is kept, so that an error
/// for each element of a long array (a field wrong in each of 10,000 boxes) costs a short walk
/// each, not one from the start of the text.
class JsonPositions {
 public:
  explicit JsonPositions(std::string text) : text_(std::move(text)) {}

  PointerPositions find(const std::string& pointer) const;

 private:
  Position at(size_t offset) const;  // needs mutex_ held
  const std::vector<size_t>& elements(size_t array) const;

  std::string text_;
  mutable std::mutex mutex_;
  mutable std::vector<size_t> line_starts_;                           // made at the first find
  mutable std::unordered_map<size_t, std::vector<size_t>> elements_;  // an array's offset -> its elements'
};

/// Line and column (1-based, in bytes) of byte `offset` of `text`.
Position position_in(std::string_view text, size_t offset);

}  // namespace olt
