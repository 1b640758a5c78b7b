// Nested tables and old spellings: finding a field by its path, and a job's old flat keys moved to
// their new places before validation (with their positions, so errors point where they were written).
#include <algorithm>
#include <functional>

#include "olt/config/params.h"

namespace olt {

using nlohmann::json;

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

void FieldTable::add_spelling(const std::string& old_key, const std::string& path) {
  if (!find(path)) throw std::logic_error("old spelling '" + old_key + "' names no field: " + path);
  renamed_.push_back({old_key, path});
}

void FieldTable::add_flat_spellings(const std::string& prefix, const std::string& section) {
  const FieldInfo* nested = find(section);
  if (!nested || nested->type != FieldType::kStruct) throw std::logic_error("no nested table " + section);
  auto taken = [&](const std::string& key) {
    return std::any_of(fields_.begin(), fields_.end(), [&](const FieldInfo& f) { return f.key == key; }) ||
           std::any_of(renamed_.begin(), renamed_.end(), [&](const Renamed& r) { return r.old_key == key; });
  };
  std::function<void(const FieldTable&, const std::string&)> add = [&](const FieldTable& table,
                                                                       const std::string& path) {
    for (const auto& f : table.fields()) {
      if (f.type == FieldType::kStruct) {
        add(*f.sub, path + "/" + f.key);
      } else if (!taken(prefix + f.key)) {
        renamed_.push_back({prefix + f.key, path + "/" + f.key});
      }
    }
  };
  add(*nested->sub, section);
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
    std::string problem = moved.value.contains(target) ? "and the job gives that place too" : "";
    for (json::json_pointer up = target.parent_pointer(); up.to_string().size() > pointer.size();
         up = up.parent_pointer())
      if (moved.value.contains(up) && !moved.value.at(up).is_object() && !moved.value.at(up).is_null())
        problem = "and '" + dotted(up.to_string().substr(pointer.size() + 1)) + "' is not a map";
    const json value = params[r.old_key];
    params.erase(r.old_key);
    if (!problem.empty()) {
      errors.push_back(doc.error_at_key(from, what + ": '" + r.old_key + "' is the old spelling of '" + dotted(r.path) +
                                                  "', " + problem + "; write only '" + dotted(r.path) + "'"));
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

}  // namespace olt
