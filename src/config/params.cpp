#include "olt/config/params.h"

#include <algorithm>
#include <cmath>
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

const FieldInfo* FieldTable::find(const std::string& path) const {
  const size_t slash = path.find('/');
  const std::string key = path.substr(0, slash);
  for (const auto& f : fields_) {
    if (f.key != key) continue;
    if (slash == std::string::npos) return &f;
    return f.type == FieldType::kStruct ? f.sub->find(path.substr(slash + 1)) : nullptr;
  }
  return nullptr;
}

namespace {

// Moves the positions remembered for `from` (and below) to `to`.
void move_positions(std::map<std::string, Position>& positions, const std::string& from, const std::string& to) {
  std::map<std::string, Position> moved;
  for (auto it = positions.begin(); it != positions.end();) {
    const std::string& p = it->first;
    if (p == from || p.rfind(from + "/", 0) == 0) {
      moved[to + p.substr(from.size())] = it->second;
      it = positions.erase(it);
    } else {
      ++it;
    }
  }
  positions.insert(moved.begin(), moved.end());
}

// `doc` with the old spellings of `table` under `pointer` moved to their new places (positions
// too, so errors point into the file where the user wrote them).
Document with_new_spellings(const Document& doc, const std::string& pointer, const FieldTable& table,
                            const std::string& what, std::vector<Diagnostic>& errors) {
  Document moved = doc;
  json& params = moved.value.at(json::json_pointer(pointer));
  for (const auto& r : table.renamed()) {
    if (!params.contains(r.old_key)) continue;
    const std::string from = pointer + "/" + pointer_escape(r.old_key), to = pointer + "/" + r.path;
    const json::json_pointer target(to);
    // Blocked where the new place is given too, or one of its enclosing keys is not a map.
    bool blocked = moved.value.contains(target);
    for (json::json_pointer up = target.parent_pointer(); !up.empty(); up = up.parent_pointer())
      blocked =
          blocked || (moved.value.contains(up) && !moved.value.at(up).is_object() && !moved.value.at(up).is_null());
    const json value = params[r.old_key];
    params.erase(r.old_key);
    if (blocked) {
      errors.push_back(doc.error_at_key(from, what + ": '" + r.old_key + "' is the old spelling of '" + dotted(r.path) +
                                                  "', and the job gives that place too; write only '" + dotted(r.path) +
                                                  "'"));
      continue;
    }
    moved.value[target] = value;
    move_positions(moved.keys, from, to);
    move_positions(moved.values, from, to);
  }
  return moved;
}

}  // namespace

json FieldTable::canonical(const Document& doc, const std::string& pointer, const fs::path& base,
                           const std::string& what, std::vector<Diagnostic>& errors) const {
  const json& given = doc.value.at(json::json_pointer(pointer));
  const bool old_spellings = given.is_object() && std::any_of(renamed_.begin(), renamed_.end(), [&](const Renamed& r) {
                               return given.contains(r.old_key);
                             });
  if (!old_spellings) return validate(doc, pointer, base, what, errors);
  return validate(with_new_spellings(doc, pointer, *this, what, errors), pointer, base, what, errors);
}

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
      const std::string guess = did_you_mean(key, known);
      if (!guess.empty()) message += "; did you mean '" + guess + "'?";
      message += " (expected one of: " + join(known) + ")";
      errors.push_back(doc.error_at_key(at, message));
      continue;
    }
    const FieldInfo& f = *field;
    const std::string name = what + ": parameter '" + key + "'";
    auto fail = [&](const std::string& problem, const std::string& where) {
      errors.push_back(doc.error_at(where, name + ": " + problem));
    };
    switch (f.type) {
      case FieldType::kBoolean:
        if (!value.is_boolean())
          fail("expected true or false, got " + show(value), at);
        else
          out[key] = value;
        break;
      case FieldType::kInteger:
      case FieldType::kNumber: {
        const std::string problem = check_number(f, value, f.type == FieldType::kInteger);
        if (!problem.empty())
          fail(problem, at);
        else
          out[key] = value;
        break;
      }
      case FieldType::kString:
        if (!value.is_string())
          fail("expected a string, got " + show(value), at);
        else
          out[key] = value;
        break;
      case FieldType::kPath: {
        if (!value.is_string() || value.get<std::string>().empty()) {
          fail("expected a non-empty path, got " + show(value), at);
          break;
        }
        const fs::path resolved = resolve_path(base, value.get<std::string>());
        std::error_code ec;
        if (f.must_exist && !fs::exists(resolved, ec))
          fail("'" + value.get<std::string>() + "' does not exist (resolved to " + resolved.string() + ")", at);
        else
          out[key] = resolved.string();
        break;
      }
      case FieldType::kChoice:
        if (!value.is_string() ||
            std::find(f.choices.begin(), f.choices.end(), value.get<std::string>()) == f.choices.end()) {
          std::string problem = "expected one of " + join(f.choices) + ", got " + show(value);
          if (value.is_string()) {
            const std::string guess = did_you_mean(value.get<std::string>(), f.choices);
            if (!guess.empty()) problem += "; did you mean '" + guess + "'?";
          }
          fail(problem, at);
        } else {
          out[key] = value;
        }
        break;
      case FieldType::kNumbers: {
        if (!value.is_array()) {
          fail("expected a list of " + (f.length ? std::to_string(f.length) + " " : std::string()) + "numbers, got " +
                   show(value),
               at);
          break;
        }
        if (f.length && value.size() != f.length) {
          fail("expected " + std::to_string(f.length) + " numbers, got " + std::to_string(value.size()), at);
          break;
        }
        bool ok = true;
        for (size_t i = 0; i < value.size(); ++i) {
          const std::string problem = check_number(f, value[i], false);
          if (!problem.empty()) {
            fail("item " + std::to_string(i) + ": " + problem, at + "/" + std::to_string(i));
            ok = false;
          }
        }
        if (ok) out[key] = value;
        break;
      }
      case FieldType::kStrings: {
        bool ok = value.is_array();
        for (const auto& item : value) ok = ok && item.is_string() && !item.get<std::string>().empty();
        if (!ok)
          fail("expected a list of non-empty strings, got " + show(value), at);
        else
          out[key] = value;
        break;
      }
      case FieldType::kStringMap: {
        bool ok = value.is_object();
        for (const auto& [entry, item] : value.items()) ok = ok && item.is_string() && !item.get<std::string>().empty();
        if (!ok)
          fail("expected a map from names to non-empty names, got " + show(value), at);
        else
          out[key] = value;
        break;
      }
      case FieldType::kIntMap: {
        if (!value.is_object()) {
          fail(std::string("expected ") + type_name(f.type) + ", got " + show(value), at);
          break;
        }
        bool ok = true;
        for (const auto& [entry, number] : value.items()) {
          const std::string problem = check_number(f, number, true);
          if (!problem.empty()) {
            fail("'" + entry + "': " + problem, at + "/" + pointer_escape(entry));
            ok = false;
          }
        }
        if (ok) out[key] = value;
        break;
      }
      case FieldType::kStructMap: {
        if (!value.is_object()) {
          fail(std::string("expected ") + type_name(f.type) + ", got " + show(value), at);
          break;
        }
        json entries = json::object();
        for (const auto& [entry, sub_value] : value.items())
          entries[entry] = f.sub->canonical(doc, at + "/" + pointer_escape(entry), base,
                                            what + ": " + key + " '" + entry + "'", errors);
        out[key] = entries;
        break;
      }
      case FieldType::kStruct:
        if (!value.is_object() && !value.is_null()) {
          fail(std::string("expected ") + type_name(f.type) + ", got " + show(value), at);
          break;
        }
        out[key] = f.sub->canonical(doc, at, base, what + ": " + key, errors);
        break;
    }
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
