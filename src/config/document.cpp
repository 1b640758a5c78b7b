#include "olt/config/document.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <regex>
#include <set>

#include "json_positions.h"

namespace olt {
namespace {

Position position_of(const YAML::Mark& mark) {
  if (mark.is_null()) return {};
  return {mark.line + 1, mark.column + 1};
}

// Plain (unquoted) scalars follow the YAML 1.2 core schema; quoted ones are strings.
// A number too large or too small for a double (1e999, 2e-3826834): underflow is 0, overflow is
// kept as text, so the parameter's type check names it instead of an exception escaping.
nlohmann::json finite_or_text(const std::string& text) {
  const double value = std::strtod(text.c_str(), nullptr);
  if (std::isfinite(value)) return value;
  return text;
}

nlohmann::json scalar(const YAML::Node& node) {
  const std::string& text = node.Scalar();
  if (node.Tag() == "!") return text;
  static const std::regex kNull("~|null|Null|NULL|");
  static const std::regex kTrue("true|True|TRUE");
  static const std::regex kFalse("false|False|FALSE");
  static const std::regex kInt("[-+]?[0-9]+");
  static const std::regex kFloat(R"([-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?)");
  static const std::regex kInf(R"([-+]?\.(inf|Inf|INF))");
  static const std::regex kNan(R"(\.(nan|NaN|NAN))");
  if (std::regex_match(text, kNull)) return nullptr;
  if (std::regex_match(text, kTrue)) return true;
  if (std::regex_match(text, kFalse)) return false;
  if (std::regex_match(text, kInt)) {
    try {
      return std::stoll(text);
    } catch (const std::out_of_range&) {
      return finite_or_text(text);
    }
  }
  if (std::regex_match(text, kFloat)) return finite_or_text(text);
  if (std::regex_match(text, kInf)) return text[0] == '-' ? -INFINITY : INFINITY;
  if (std::regex_match(text, kNan)) return NAN;
  return text;
}

// `budget`: how many more values the document may expand to. YAML aliases repeat a node wherever
// they stand, so a 1 KB file of nested aliases can stand for billions of values.
nlohmann::json convert(const YAML::Node& node, const std::string& pointer, Document& doc, size_t& budget) {
  if (budget == 0) {
    const Position at = position_of(node.Mark());
    throw InputError({{doc.file, at.line, at.column,
                       "the document expands to too many values (YAML aliases repeating each other?)"}});
  }
  --budget;
  doc.values[pointer] = position_of(node.Mark());
  switch (node.Type()) {
    case YAML::NodeType::Map: {
      nlohmann::json object = nlohmann::json::object();
      for (const auto& item : node) {
        if (!item.first.IsScalar()) {
          const Position at = position_of(item.first.Mark());
          throw InputError({{doc.file, at.line, at.column, "a key must be a plain string"}});
        }
        const std::string key = item.first.Scalar();
        const std::string child = pointer + "/" + pointer_escape(key);
        if (object.contains(key)) {  // named where it is given again
          const Position at = position_of(item.first.Mark());
          throw InputError({{doc.file, at.line, at.column, "duplicate key '" + key + "'"}});
        }
        doc.keys[child] = position_of(item.first.Mark());
        object[key] = convert(item.second, child, doc, budget);
      }
      return object;
    }
    case YAML::NodeType::Sequence: {
      nlohmann::json array = nlohmann::json::array();
      for (size_t i = 0; i < node.size(); ++i)
        array.push_back(convert(node[i], pointer + "/" + std::to_string(i), doc, budget));
      return array;
    }
    case YAML::NodeType::Scalar:
      return scalar(node);
    default:
      return nullptr;
  }
}

}  // namespace

std::string pointer_escape(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

Position Document::where(const std::string& pointer) const {
  if (json_positions) return json_positions->find(pointer).value;
  for (std::string p = pointer;; p = p.substr(0, p.rfind('/'))) {
    if (auto it = values.find(p); it != values.end() && it->second.line > 0) return it->second;
    if (auto it = keys.find(p); it != keys.end()) return it->second;
    if (p.empty()) return {};
  }
}

Position Document::where_key(const std::string& pointer) const {
  if (json_positions) {
    const PointerPositions found = json_positions->find(pointer);
    return found.key.line > 0 ? found.key : found.value;
  }
  if (auto it = keys.find(pointer); it != keys.end()) return it->second;
  return where(pointer);
}

Diagnostic Document::error_at(const std::string& pointer, const std::string& message) const {
  const Position p = where(pointer);
  return {file, p.line, p.column, message};
}

Diagnostic Document::error_at_key(const std::string& pointer, const std::string& message) const {
  const Position p = where_key(pointer);
  return {file, p.line, p.column, message};
}

Document parse_yaml(const std::string& file, const std::string& text) {
  check_utf8(file, text);
  Document doc;
  doc.file = file;
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    const Position p = position_of(e.mark);
    throw InputError({{file, p.line, p.column, "YAML syntax error: " + e.msg}});
  }
  // 100,000 values, and ten per byte of text for large plain documents (a value takes 2 bytes at least).
  size_t budget = 100000 + 10 * text.size();
  doc.value = convert(root, "", doc, budget);
  return doc;
}

Document load_yaml(const fs::path& file) { return parse_yaml(file.string(), read_file(file)); }

}  // namespace olt

namespace olt {

namespace {

// nlohmann keeps the last of two equal keys of an object: a second "boxes" would silently replace
// the first. A pass of parser events finds them, with the keys of each open object. (A parser
// callback could, but nlohmann's callback parser takes time quadratic in an array's length: 4 s
// for 100,000 boxes.)
class DuplicateKeys : public nlohmann::json_sax<nlohmann::json> {
 public:
  std::optional<std::string> found;

  bool start_object(std::size_t) override {
    open_.emplace_back();
    return true;
  }
  bool end_object() override {
    open_.pop_back();
    return true;
  }
  bool key(string_t& key) override {
    if (!open_.back().insert(key).second) found = key;
    return !found;
  }
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  std::vector<std::set<std::string>> open_;
};

}  // namespace

Document parse_json_document(const std::string& file, const std::string& text) {
  nlohmann::json value;
  try {
    value = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    const Position at = position_in(text, e.byte > 0 ? e.byte - 1 : 0);  // e.byte counts from 1
    std::string message = e.what();
    if (auto from = message.find("syntax error"); from != std::string::npos) message = message.substr(from);
    throw InputError({{file, at.line, at.column, "JSON " + message}});
  } catch (const nlohmann::json::exception& e) {
    // Not a syntax error (a number that overflows a double, ...): no byte offset; the position of
    // the literal the message quotes, where it can be found.
    std::string message = e.what();
    Position literal;
    const auto quote = message.find('\'');
    const auto end = quote == std::string::npos ? std::string::npos : message.find('\'', quote + 1);
    if (end != std::string::npos)
      if (const auto at = text.find(message.substr(quote + 1, end - quote - 1)); at != std::string::npos)
        literal = position_in(text, at);
    if (auto at = message.find("] "); at != std::string::npos) message = message.substr(at + 2);
    throw InputError({{file, literal.line, literal.column, "JSON: " + message}});
  }
  DuplicateKeys duplicates;
  nlohmann::json::sax_parse(text, &duplicates);
  if (const auto& duplicate = duplicates.found) {
    try {
      parse_yaml(file, text);  // names it with its line
    } catch (const InputError& e) {
      if (std::string(e.what()).find("duplicate key") != std::string::npos) throw;
    }
    throw InputError({{file, 0, 0, "duplicate key '" + *duplicate + "'"}});
  }
  Document doc;
  doc.file = file;
  doc.json_positions = std::make_shared<const JsonPositions>(text);
  doc.value = std::move(value);
  return doc;
}

}  // namespace olt
