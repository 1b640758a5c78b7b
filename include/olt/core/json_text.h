#pragma once
// Documents too big to hold as one JSON value (a manifest of 80,000 files, the records of 10,000
// frames) written a member at a time, byte-identical to nlohmann::json's dump(1) of the whole.
#include <nlohmann/json.hpp>
#include <string>

namespace olt {

/// Appends `value` as dump(1) writes it `depth` levels deep in a document: every line after its first
/// indented by `depth` more spaces.
void append_nested(std::string& text, const nlohmann::json& value, int depth);

}  // namespace olt
