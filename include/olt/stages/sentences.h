#pragma once
// What a stage made, in one plain sentence for the run's log, from the summary it returned
// (summary.json): counts with their units, shares as percentages, warnings counted. A kind without a
// sentence of its own (or a summary it does not recognize) is shown as its JSON.
#include <nlohmann/json.hpp>
#include <string>

namespace olt {

std::string stage_sentence(const std::string& kind, const nlohmann::json& summary);

/// "12.3%" of part in whole ("0%" when whole is 0); shares below 0.1% keep two significant digits.
std::string percent(double part, double whole);

}  // namespace olt
