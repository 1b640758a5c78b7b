#include "json_fields.h"

#include <cmath>

namespace olt {

const nlohmann::json& FieldReader::at(const std::string& pointer, const std::string& what) {
  static const nlohmann::json kNull;
  const nlohmann::json::json_pointer p(pointer);
  if (!doc_.value.contains(p)) {
    error(pointer, what + ": missing");
    return kNull;
  }
  return doc_.value.at(p);
}

double FieldReader::number(const std::string& pointer, const std::string& what) {
  const nlohmann::json& v = at(pointer, what);
  if (v.is_null()) return 0;
  if (!v.is_number() || !std::isfinite(v.get<double>())) {
    error(pointer, what + ": expected a finite number, got " + v.dump());
    return 0;
  }
  return v.get<double>();
}

std::string FieldReader::text(const std::string& pointer, const std::string& what) {
  const nlohmann::json& v = at(pointer, what);
  if (v.is_null()) return "";
  if (v.is_number_integer()) return std::to_string(v.get<long long>());
  if (!v.is_string() || v.get<std::string>().empty()) {
    error(pointer, what + ": expected a non-empty string, got " + v.dump());
    return "";
  }
  return v.get<std::string>();
}

Eigen::Vector3d FieldReader::vector(const std::string& pointer, const std::string& what,
                                    const std::vector<std::string>& keys) {
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) out[k] = number(pointer + "/" + keys[k], what + "." + keys[k]);
  return out;
}

void FieldReader::error(const std::string& pointer, const std::string& message) {
  errors_.push_back(doc_.error_at(pointer, message));
}

void FieldReader::warn(const std::string& pointer, const std::string& message) {
  warnings_.push_back(doc_.error_at(pointer, message));
}

void FieldReader::throw_if_errors() const {
  if (!errors_.empty()) throw InputError(errors_);
}

}  // namespace olt
