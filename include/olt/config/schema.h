#pragma once
// JSON Schema validation (valijson, draft 7) of documents against the schemas in schemas/, which are
// compiled into the binary.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "olt/config/document.h"

namespace olt {

/// The parsed schema `name` (e.g. "job.schema.json") from the embedded copies of schemas/.
const nlohmann::json& schema(std::string_view name);

/// Every schema violation in `doc`, one diagnostic per failing location, at its position.
std::vector<Diagnostic> validate_against_schema(const Document& doc, std::string_view schema_name);

}  // namespace olt
