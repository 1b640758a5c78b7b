#pragma once
// Documents too big to hold as one JSON value (a manifest of 80,000 files, the records of 10,000
// frames) written a member at a time, byte-identical to nlohmann::json's dump(1) of the whole.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace olt {

/// Appends `value` as dump(1) writes it `depth` levels deep in a document: every line after its first
/// indented by `depth` more spaces.
void append_nested(std::string& text, const nlohmann::json& value, int depth);

/// Appends, as dump(1) writes it `depth` levels deep, an array of `count` elements made one at a time
/// by `element(i)`.
void append_array(std::string& text, size_t count, const std::function<nlohmann::json(size_t)>& element, int depth);

}  // namespace olt
