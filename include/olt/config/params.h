#pragma once
// Stage parameters: each stage kind describes its config struct once, as a table of fields bound to
// struct members. The table validates a job's `params:` (type, range, choices, unknown keys with a
// "did you mean"), fills defaults from the struct, resolves paths against the job's folder, and
// gives the canonical JSON that enters the cache key. A test checks it against schemas/.
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "olt/config/document.h"

namespace olt {

enum class FieldType {
  kBoolean,
  kInteger,
  kNumber,
  kString,
  kPath,
  kChoice,
  kNumbers,
  kStrings,
  kIntMap,
  kStringMap,
  kStructMap,
  kStruct
};

class FieldTable;

struct FieldInfo {
  std::string key;
  FieldType type = FieldType::kNumber;
  std::string doc;  ///< one line, with the unit
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool exclusive_min = false;             ///< value must be > min rather than >= min
  std::vector<std::string> choices;       ///< kChoice
  size_t length = 0;                      ///< kNumbers: exact length; 0 = any length
  bool must_exist = false;                ///< kPath: the file or folder must exist when given
  std::shared_ptr<const FieldTable> sub;  ///< kStructMap: table of each entry; kStruct: the nested table
};

/// An old spelling of a parameter, still accepted: `old_key` (at the table's top level) stands for
/// the field at `path` ("registration/solver/method").
struct Renamed {
  std::string old_key;
  std::string path;
};

struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool exclusive_min = false;
};
inline Range positive() { return {0, std::numeric_limits<double>::infinity(), true}; }
inline Range non_negative() { return {0, std::numeric_limits<double>::infinity(), false}; }
inline Range between(double lo, double hi) { return {lo, hi, false}; }

class FieldTable {
 public:
  virtual ~FieldTable() = default;
  const std::vector<FieldInfo>& fields() const { return fields_; }
  const std::vector<Renamed>& renamed() const { return renamed_; }
  virtual nlohmann::json defaults() const = 0;
  /// The field at `path` ("registration/solver/method"), through nested tables; null if none.
  const FieldInfo* find(const std::string& path) const;

  /// Validates the object at `pointer` of `doc`; appends every problem to `errors`; returns the
  /// canonical params (defaults filled in, paths absolute). `what` names the owner in messages.
  nlohmann::json canonical(const Document& doc, const std::string& pointer, const fs::path& base,
                           const std::string& what, std::vector<Diagnostic>& errors) const;

 protected:
  /// Throws std::logic_error when `path` names no field (a mistake in a table, found at start-up).
  void add_spelling(const std::string& old_key, const std::string& path);
  void add_flat_spellings(const std::string& prefix, const std::string& section);

  std::vector<FieldInfo> fields_;
  std::vector<Renamed> renamed_;

 private:
  nlohmann::json validate(const Document& doc, const std::string& pointer, const fs::path& base,
                          const std::string& what, std::vector<Diagnostic>& errors) const;
};

/// The names of an enum's values in a job, for Params::choice.
template <class Enum>
using Names = std::vector<std::pair<std::string, Enum>>;

/// The name of `value` in `names` ("" where it has none).
template <class Enum>
std::string name_in(const Names<Enum>& names, Enum value) {
  for (const auto& [name, e] : names)
    if (e == value) return name;
  return "";
}

template <class Config>
class Params : public FieldTable {
 public:
  using Setter = std::function<void(Config&, const nlohmann::json&)>;
  using Getter = std::function<nlohmann::json(const Config&)>;

  template <class Member>
  Params& boolean(const char* key, Member m, const char* doc) {
    return add<bool>(field(key, FieldType::kBoolean, doc), m);
  }
  template <class Member>
  Params& integer(const char* key, Member m, Range r, const char* doc) {
    return add<int>(ranged(field(key, FieldType::kInteger, doc), r), m);
  }
  template <class Member>
  Params& number(const char* key, Member m, Range r, const char* doc) {
    return add<double>(ranged(field(key, FieldType::kNumber, doc), r), m);
  }
  template <class Member>
  Params& text(const char* key, Member m, const char* doc) {
    return add<std::string>(field(key, FieldType::kString, doc), m);
  }
  /// A file or folder, resolved against the job file's folder; "" when not given.
  template <class Member>
  Params& path(const char* key, Member m, bool must_exist, const char* doc) {
    FieldInfo f = field(key, FieldType::kPath, doc);
    f.must_exist = must_exist;
    return add<std::string>(f, m);
  }
  template <class Member>
  Params& choice(const char* key, Member m, std::vector<std::string> choices, const char* doc) {
    FieldInfo f = field(key, FieldType::kChoice, doc);
    f.choices = std::move(choices);
    return add<std::string>(f, m);
  }
  /// A choice bound to an enum member: each name with its value, in the order `olt help` lists them.
  /// The names are what jobs, the canonical JSON and the schema say; the code sees only the enum.
  template <class Member, class Enum>
  Params& choice(const char* key, Member m, const std::vector<std::pair<std::string, Enum>>& names, const char* doc) {
    FieldInfo f = field(key, FieldType::kChoice, doc);
    for (const auto& n : names) f.choices.push_back(n.first);
    fields_.push_back(std::move(f));
    setters_.push_back([m, names](Config& c, const nlohmann::json& v) {
      for (const auto& [name, value] : names)
        if (name == v.get<std::string>()) std::invoke(m, c) = value;
    });
    getters_.push_back(
        [m, names](const Config& c) { return nlohmann::json(name_in(names, std::invoke(m, const_cast<Config&>(c)))); });
    return *this;
  }
  /// A list of numbers; `length` 0 accepts any length; an empty list means "not given".
  template <class Member>
  Params& numbers(const char* key, Member m, size_t length, const char* doc) {
    FieldInfo f = field(key, FieldType::kNumbers, doc);
    f.length = length;
    return add<std::vector<double>>(f, m);
  }
  template <class Member>
  Params& strings(const char* key, Member m, const char* doc) {
    return add<std::vector<std::string>>(field(key, FieldType::kStrings, doc), m);
  }
  template <class Member>
  Params& string_map(const char* key, Member m, const char* doc) {
    return add<std::map<std::string, std::string>>(field(key, FieldType::kStringMap, doc), m);
  }
  template <class Member>
  Params& int_map(const char* key, Member m, Range r, const char* doc) {
    return add<std::map<std::string, int>>(ranged(field(key, FieldType::kIntMap, doc), r), m);
  }
  template <class Sub>
  Params& struct_map(const char* key, std::map<std::string, Sub> Config::*m, std::shared_ptr<const Params<Sub>> sub,
                     const char* doc) {
    FieldInfo f = field(key, FieldType::kStructMap, doc);
    f.sub = sub;
    fields_.push_back(f);
    setters_.push_back([m, sub](Config& c, const nlohmann::json& v) {
      (c.*m).clear();
      for (const auto& [name, entry] : v.items()) (c.*m)[name] = sub->from_json(entry);
    });
    getters_.push_back([m, sub](const Config& c) {
      nlohmann::json out = nlohmann::json::object();
      for (const auto& [name, entry] : c.*m) out[name] = sub->to_json(entry);
      return out;
    });
    return *this;
  }

  /// A nested table under `key`: in YAML a map of the sub-struct's own fields (`m` a member pointer
  /// or a callable giving the sub-struct of a Config).
  template <class Sub, class Member>
  Params& nested(const char* key, Member m, std::shared_ptr<const Params<Sub>> sub, const char* doc) {
    FieldInfo f = field(key, FieldType::kStruct, doc);
    f.sub = sub;
    fields_.push_back(f);
    setters_.push_back([m, sub](Config& c, const nlohmann::json& v) { std::invoke(m, c) = sub->from_json(v); });
    getters_.push_back([m, sub](const Config& c) { return sub->to_json(std::invoke(m, const_cast<Config&>(c))); });
    return *this;
  }
  /// Every field of `sub` at this table's level, bound through `get` to the sub-struct of a Config
  /// (one field list serving a flat table and a nested one).
  template <class Sub, class Get>
  Params& embed(Get get, const Params<Sub>& sub) {
    for (size_t i = 0; i < sub.fields_.size(); ++i) {
      fields_.push_back(sub.fields_[i]);
      auto set = sub.setters_[i];
      auto read = sub.getters_[i];
      setters_.push_back([get, set](Config& c, const nlohmann::json& v) { set(std::invoke(get, c), v); });
      getters_.push_back([get, read](const Config& c) { return read(std::invoke(get, const_cast<Config&>(c))); });
    }
    return *this;
  }
  /// Accepts `old_key` for the field at `path` (old job files keep working; the canonical params,
  /// and so the cache keys, use the new place).
  Params& renamed(const char* old_key, const char* path) {
    add_spelling(old_key, path);
    return *this;
  }
  /// Accepts, for every field inside the nested table `section`, its key after `prefix` at this
  /// table's top level (the flat keys of earlier versions: laser_huber_m for laser/matching/huber_m),
  /// except where that is a key of this table. Call after declaring every field.
  Params& renamed_flat(const char* prefix, const char* section) {
    add_flat_spellings(prefix, section);
    return *this;
  }

  /// Trusted conversion of canonical params (validated beforehand) into the struct.
  Config from_json(const nlohmann::json& params) const {
    Config config;
    for (size_t i = 0; i < fields_.size(); ++i)
      if (params.contains(fields_[i].key)) setters_[i](config, params.at(fields_[i].key));
    return config;
  }
  nlohmann::json to_json(const Config& config) const {
    nlohmann::json out = nlohmann::json::object();
    for (size_t i = 0; i < fields_.size(); ++i) out[fields_[i].key] = getters_[i](config);
    return out;
  }
  nlohmann::json defaults() const override {
    const Config config;  // a named object: GCC 12 misreads a temporary's strings as uninitialised
    return to_json(config);
  }

 private:
  static FieldInfo field(const char* key, FieldType type, const char* doc) {
    FieldInfo f;
    f.key = key;
    f.type = type;
    f.doc = doc;
    return f;
  }
  static FieldInfo ranged(FieldInfo f, Range r) {
    f.min = r.min;
    f.max = r.max;
    f.exclusive_min = r.exclusive_min;
    return f;
  }
  // `m` is a member pointer or a callable giving the field of a Config (nested structs).
  template <class T, class Member>
  Params& add(FieldInfo f, Member m) {
    fields_.push_back(std::move(f));
    setters_.push_back([m](Config& c, const nlohmann::json& v) { std::invoke(m, c) = v.get<T>(); });
    getters_.push_back([m](const Config& c) { return nlohmann::json(std::invoke(m, const_cast<Config&>(c))); });
    return *this;
  }
  std::vector<Setter> setters_;
  std::vector<Getter> getters_;
  template <class>
  friend class Params;
};

/// A field's path ("registration/solver/method") as users read it: registration.solver.method.
std::string dotted(std::string path);

/// The words separated by ", " (for messages: choices, keys).
std::string join(const std::vector<std::string>& words);

/// What a field accepts, in words: "a number in [0, 1]", "one of gicp, icp", ...
std::string field_expectation(const FieldInfo& field);

/// The closest of `candidates` to `word` by edit distance, if close enough to be a likely typo.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace olt

namespace olt {

/// The JSON Schema (draft 7) of a parameter table; schemas/job.schema.json holds one per stage
/// kind, and a test checks they are equal.
nlohmann::json params_schema(const FieldTable& table);

/// Every parameter of a table, for `olt help KIND`: per field "key: doc", then what it accepts and
/// its default, each line starting with `indent` (nested tables: one level further).
std::string params_help(const FieldTable& table, const std::string& indent = "  ");

}  // namespace olt
