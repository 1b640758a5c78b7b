#pragma once
// A YAML or JSON document loaded as nlohmann::json, able to say where each key and value stood in
// the file so every error can be reported as FILE:LINE:COLUMN: a YAML document's positions are
// kept as it is parsed, a JSON document's are found in its text when an error asks.
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "olt/core/error.h"
#include "olt/core/fs.h"

namespace olt {

struct Position {
  int line = 0;    ///< 1-based; 0 = unknown
  int column = 0;  ///< 1-based
};

struct Document {
  std::string file;                        ///< as given, for messages
  nlohmann::json value;                    ///< the content, YAML 1.2 core types
  std::map<std::string, Position> keys;    ///< JSON pointer -> position of its key (YAML)
  std::map<std::string, Position> values;  ///< JSON pointer -> position of its value (YAML)
  /// A JSON document's positions, found in its text when an error asks for them (the tables above
  /// stay empty for it: made for every value, they cost more than the parse itself).
  std::shared_ptr<const class JsonPositions> json_positions;

  /// Position of the value at `pointer`, else of its key, else of the nearest enclosing value.
  Position where(const std::string& pointer) const;
  /// Position of the key at `pointer` (for unknown-key errors), else where(pointer).
  Position where_key(const std::string& pointer) const;
  Diagnostic error_at(const std::string& pointer, const std::string& message) const;
  Diagnostic error_at_key(const std::string& pointer, const std::string& message) const;
};

/// Parses YAML (JSON is accepted too). Throws InputError with the parser's position.
Document parse_yaml(const std::string& file, const std::string& text);
Document load_yaml(const fs::path& file);

/// Escapes a key for a JSON pointer ("~" -> "~0", "/" -> "~1").
std::string pointer_escape(const std::string& key);

}  // namespace olt

namespace olt {

/// Parses strict JSON (nlohmann); schema and semantic errors in JSON files carry FILE:LINE:COLUMN
/// too, found in the text when asked for. Throws InputError on a syntax error or a duplicate key.
Document parse_json_document(const std::string& file, const std::string& text);

}  // namespace olt
