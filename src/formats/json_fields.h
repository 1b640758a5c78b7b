#pragma once
// Reading typed fields out of a positioned JSON document, collecting one diagnostic per problem
// (private to the format readers).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "olt/config/document.h"

namespace olt {

/// {"x": v.x, "y": v.y, "z": v.z}, the vector form every tool format uses.
inline nlohmann::json xyz_json(const Eigen::Vector3d& v) { return {{"x", v.x()}, {"y", v.y()}, {"z", v.z()}}; }

class FieldReader {
 public:
  explicit FieldReader(const Document& doc) : doc_(doc) {}

  /// The value at `pointer`, or null after recording "`what`: missing".
  const nlohmann::json& at(const std::string& pointer, const std::string& what);
  double number(const std::string& pointer, const std::string& what);
  std::string text(const std::string& pointer, const std::string& what);
  /// {x, y, z} members of the object at `pointer` (or the keys given).
  Eigen::Vector3d vector(const std::string& pointer, const std::string& what,
                         const std::vector<std::string>& keys = {"x", "y", "z"});
  void error(const std::string& pointer, const std::string& message);
  /// Throws InputError with everything recorded, if anything was.
  void throw_if_errors() const;
  /// A doubt that does not stop reading, positioned like an error.
  void warn(const std::string& pointer, const std::string& message);
  const std::vector<Diagnostic>& warnings() const { return warnings_; }

 private:
  const Document& doc_;
  std::vector<Diagnostic> errors_;
  std::vector<Diagnostic> warnings_;
};

}  // namespace olt
