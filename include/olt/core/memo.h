#pragma once
// Bytes remembered by what they are made of (a picture by its scene, region and boxes): the runtime
// keeps them in the cache (StageContext::memo); code that runs without a cache makes them every time.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace olt {

/// The bytes `make` returns for `record` (every input as a value or a digest), made only where they
/// were not made before for the same record.
using Memo = std::function<std::string(const nlohmann::json& record, const std::function<std::string()>& make)>;

/// The Memo that remembers nothing: `make` every time.
inline std::string make_every_time(const nlohmann::json&, const std::function<std::string()>& make) { return make(); }

}  // namespace olt
