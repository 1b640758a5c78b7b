// Nested tables and old spellings: finding a field by its path, and a job's old flat keys moved to
// their new places before validation (with their positions, so errors point where they were written).
#include <algorithm>

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

}  // namespace olt
