#include "olt/config/params.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace olt {
namespace {

using nlohmann::json;

std::string show(const json& value) {
  // Replace, not throw, where a string is not UTF-8: the message is about the value's type.
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

const char* type_name(FieldType type) {
  switch (type) {
    case FieldType::kBoolean:
      return "true or false";
    case FieldType::kInteger:
      return "an integer";
    case FieldType::kNumber:
      return "a number";
    case FieldType::kString:
      return "a string";
    case FieldType::kPath:
      return "a path (string)";
    case FieldType::kChoice:
      return "a string";
    case FieldType::kNumbers:
      return "a list of numbers";
    case FieldType::kStrings:
      return "a list of strings";
    case FieldType::kStringMap:
      return "a map from names to names";
    case FieldType::kIntMap:
      return "a map from names to integers";
    case FieldType::kStructMap:
      return "a map from names to parameter maps";
    case FieldType::kStruct:
      return "a map of parameters";
  }
  return "?";
}

std::string range_text(const FieldInfo& f) {
  std::ostringstream text;
  const bool lo = std::isfinite(f.min), hi = std::isfinite(f.max);
  if (lo && hi)
    text << "in [" << f.min << ", " << f.max << "]";
  else if (lo)
    text << (f.exclusive_min ? "> " : ">= ") << f.min;
  else if (hi)
    text << "<= " << f.max;
  return text.str();
}

bool in_range(const FieldInfo& f, double v) {
  if (f.exclusive_min ? !(v > f.min) : !(v >= f.min)) return false;
  return v <= f.max;
}

// Checks one number against the field's range; returns an error message or "".
std::string check_number(const FieldInfo& f, const json& v, bool integer) {
  if (integer ? !v.is_number_integer() : !v.is_number())
    return std::string("expected ") + (integer ? "an integer" : "a number") + ", got " + show(v);
  if (!std::isfinite(v.get<double>())) return "expected a finite number, got " + show(v);
  if (!in_range(f, v.get<double>())) return "expected " + range_text(f) + ", got " + show(v);
  return "";
}

}  // namespace

std::string dotted(std::string path) {
  std::replace(path.begin(), path.end(), '/', '.');
  return path;
}

std::string join(const std::vector<std::string>& words) {
  std::string text;
  for (const auto& w : words) text += (text.empty() ? "" : ", ") + w;
  return text;
}

std::string field_expectation(const FieldInfo& f) {
  std::string text = type_name(f.type);
  if (f.type == FieldType::kChoice) return "one of " + join(f.choices);
  const std::string range = range_text(f);
  if (!range.empty()) text += " " + range;
  if (f.type == FieldType::kNumbers && f.length) text += " (" + std::to_string(f.length) + ")";
  return text;
}

namespace {

// One given value being checked: where it is, what to call it, where problems go.
struct ValueCheck {
  const Document& doc;
  const std::string& at;    ///< its JSON pointer
  const std::string& name;  ///< "stage 's' (kind): parameter 'key'"
  const fs::path& base;     ///< the job's folder, for paths
  std::vector<Diagnostic>& errors;
  void fail(const std::string& problem) const { fail_at(problem, at); }
  void fail_at(const std::string& problem, const std::string& where) const {
    errors.push_back(doc.error_at(where, name + ": " + problem));
  }
};

std::optional<json> scalar_value(const FieldInfo& f, const json& value, const ValueCheck& c) {
  std::string problem;
  if (f.type == FieldType::kBoolean && !value.is_boolean()) problem = "expected true or false, got " + show(value);
  if (f.type == FieldType::kInteger || f.type == FieldType::kNumber)
    problem = check_number(f, value, f.type == FieldType::kInteger);
  if (f.type == FieldType::kString && !value.is_string()) problem = "expected a string, got " + show(value);
  if (f.type == FieldType::kChoice && (!value.is_string() || std::find(f.choices.begin(), f.choices.end(),
                                                                       value.get<std::string>()) == f.choices.end())) {
    problem = "expected one of " + join(f.choices) + ", got " + show(value);
    const std::string guess = value.is_string() ? did_you_mean(value.get<std::string>(), f.choices) : "";
    if (!guess.empty()) problem += "; did you mean '" + guess + "'?";
  }
  if (!problem.empty()) {
    c.fail(problem);
    return std::nullopt;
  }
  return value;
}

std::optional<json> path_value(const FieldInfo& f, const json& value, const ValueCheck& c) {
  if (!value.is_string() || value.get<std::string>().empty()) {
    c.fail("expected a non-empty path, got " + show(value));
    return std::nullopt;
  }
  const fs::path resolved = resolve_path(c.base, value.get<std::string>());
  std::error_code ec;
  if (f.must_exist && !fs::exists(resolved, ec)) {
    c.fail("'" + value.get<std::string>() + "' does not exist (resolved to " + resolved.string() + ")");
    return std::nullopt;
  }
  return resolved.string();
}

std::optional<json> numbers_value(const FieldInfo& f, const json& value, const ValueCheck& c) {
  if (!value.is_array()) {
    c.fail("expected a list of " + (f.length ? std::to_string(f.length) + " " : std::string()) + "numbers, got " +
           show(value));
    return std::nullopt;
  }
  if (f.length && value.size() != f.length) {
    c.fail("expected " + std::to_string(f.length) + " numbers, got " + std::to_string(value.size()));
    return std::nullopt;
  }
  bool ok = true;
  for (size_t i = 0; i < value.size(); ++i) {
    const std::string problem = check_number(f, value[i], false);
    if (!problem.empty()) c.fail_at("item " + std::to_string(i) + ": " + problem, c.at + "/" + std::to_string(i));
    ok = ok && problem.empty();
  }
  return ok ? std::optional<json>(value) : std::nullopt;
}

std::optional<json> names_value(const FieldInfo& f, const json& value, const ValueCheck& c) {
  const bool list = f.type == FieldType::kStrings;
  bool ok = list ? value.is_array() : value.is_object();
  for (const auto& item : value) ok = ok && item.is_string() && !item.get<std::string>().empty();
  if (ok) return value;
  c.fail(list ? "expected a list of non-empty strings, got " + show(value)
              : "expected a map from names to non-empty names, got " + show(value));
  return std::nullopt;
}

std::optional<json> int_map_value(const FieldInfo& f, const json& value, const ValueCheck& c) {
  if (!value.is_object()) {
    c.fail(std::string("expected ") + type_name(f.type) + ", got " + show(value));
    return std::nullopt;
  }
  bool ok = true;
  for (const auto& [entry, number] : value.items()) {
    const std::string problem = check_number(f, number, true);
    if (!problem.empty()) c.fail_at("'" + entry + "': " + problem, c.at + "/" + pointer_escape(entry));
    ok = ok && problem.empty();
  }
  return ok ? std::optional<json>(value) : std::nullopt;
}

// Nested tables: each entry of a map of tables (kStructMap), or one table (kStruct).
std::optional<json> table_value(const FieldInfo& f, const json& value, const ValueCheck& c, const std::string& what) {
  const bool one = f.type == FieldType::kStruct;
  if (!value.is_object() && !(one && value.is_null())) {
    c.fail(std::string("expected ") + type_name(f.type) + ", got " + show(value));
    return std::nullopt;
  }
  if (one) return f.sub->canonical(c.doc, c.at, c.base, what + ": " + f.key, c.errors);
  json entries = json::object();
  for (const auto& [entry, unused] : value.items())
    entries[entry] = f.sub->canonical(c.doc, c.at + "/" + pointer_escape(entry), c.base,
                                      what + ": " + f.key + " '" + entry + "'", c.errors);
  return entries;
}

std::optional<json> checked_value(const FieldInfo& f, const json& value, const ValueCheck& c, const std::string& what) {
  switch (f.type) {
    case FieldType::kPath:
      return path_value(f, value, c);
    case FieldType::kNumbers:
      return numbers_value(f, value, c);
    case FieldType::kStrings:
    case FieldType::kStringMap:
      return names_value(f, value, c);
    case FieldType::kIntMap:
      return int_map_value(f, value, c);
    case FieldType::kStructMap:
    case FieldType::kStruct:
      return table_value(f, value, c, what);
    default:
      return scalar_value(f, value, c);
  }
}

// The dotted place of the first field named `key` inside a nested table ("" where none is).
std::string nested_place(const FieldTable& table, const std::string& key, const std::string& prefix = "") {
  for (const auto& f : table.fields()) {
    if (f.type != FieldType::kStruct) continue;
    const std::string place = prefix + f.key + ".";
    for (const auto& inner : f.sub->fields())
      if (inner.key == key && inner.type != FieldType::kStruct) return place + key;
    if (const std::string deeper = nested_place(*f.sub, key, place); !deeper.empty()) return deeper;
  }
  return "";
}

}  // namespace

json FieldTable::validate(const Document& doc, const std::string& pointer, const fs::path& base,
                          const std::string& what, std::vector<Diagnostic>& errors) const {
  json out = defaults();
  const json& given = doc.value.at(json::json_pointer(pointer));
  if (given.is_null()) return out;
  if (!given.is_object()) {
    errors.push_back(doc.error_at(pointer, what + ": expected a map of parameters, got " + show(given)));
    return out;
  }
  std::vector<std::string> known;
  for (const auto& f : fields_) known.push_back(f.key);
  for (const auto& [key, value] : given.items()) {
    const std::string at = pointer + "/" + pointer_escape(key);
    const std::string& key_name = key;  // a structured binding cannot be captured in C++17
    auto field = std::find_if(fields_.begin(), fields_.end(), [&](const auto& f) { return f.key == key_name; });
    if (field == fields_.end()) {
      std::string message = what + ": unknown parameter '" + key + "'";
      std::string guess = did_you_mean(key, known);
      if (guess.empty()) guess = nested_place(*this, key);  // a nested setting written at the top
      if (!guess.empty()) message += "; did you mean '" + guess + "'?";
      errors.push_back(doc.error_at_key(at, message + " (expected one of: " + join(known) + ")"));
      continue;
    }
    const std::string name = what + ": parameter '" + key + "'";
    if (auto checked = checked_value(*field, value, {doc, at, name, base, errors}, what)) out[key] = *checked;
  }
  return out;
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  auto distance = [](const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t diagonal = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t above = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
        diagonal = above;
      }
    }
    return row[b.size()];
  };
  std::string best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const size_t d = distance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

}  // namespace olt
