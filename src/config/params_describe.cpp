// Descriptions of a parameter table for others: its JSON Schema (schemas/job.schema.json) and the
// text of `olt help KIND`.
#include <cmath>

#include "olt/config/params.h"

namespace olt {

using nlohmann::json;

namespace {

json field_schema(const FieldInfo& f) {
  json p = {{"description", f.doc}};
  auto bounds = [&](json& target) {
    if (std::isfinite(f.min)) target[f.exclusive_min ? "exclusiveMinimum" : "minimum"] = f.min;
    if (std::isfinite(f.max)) target["maximum"] = f.max;
  };
  switch (f.type) {
    case FieldType::kBoolean:
      p["type"] = "boolean";
      break;
    case FieldType::kInteger:
      p["type"] = "integer";
      bounds(p);
      break;
    case FieldType::kNumber:
      p["type"] = "number";
      bounds(p);
      break;
    case FieldType::kString:
      p["type"] = "string";
      break;
    case FieldType::kPath:
      p["type"] = "string";
      p["minLength"] = 1;
      break;
    case FieldType::kChoice:
      p["enum"] = f.choices;
      break;
    case FieldType::kNumbers:
      p["type"] = "array";
      p["items"] = {{"type", "number"}};
      if (f.length) p["minItems"] = p["maxItems"] = f.length;
      break;
    case FieldType::kStrings:
      p["type"] = "array";
      p["items"] = {{"type", "string"}, {"minLength", 1}};
      break;
    case FieldType::kStringMap:
      p["type"] = "object";
      p["additionalProperties"] = {{"type", "string"}, {"minLength", 1}};
      break;
    case FieldType::kIntMap: {
      json item = {{"type", "integer"}};
      bounds(item);
      p["type"] = "object";
      p["additionalProperties"] = item;
      break;
    }
    case FieldType::kStructMap:
      p["type"] = "object";
      p["additionalProperties"] = params_schema(*f.sub);
      break;
    case FieldType::kStruct:
      p.update(params_schema(*f.sub));
      break;
  }
  return p;
}

}  // namespace

nlohmann::json params_schema(const FieldTable& table) {
  json properties = json::object();
  for (const auto& f : table.fields()) properties[f.key] = field_schema(f);
  for (const auto& r : table.renamed()) {
    const FieldInfo* target = table.find(r.path);
    if (!target) throw std::logic_error("old spelling " + r.old_key + " names no field: " + r.path);
    json p = field_schema(*target);
    p["description"] = "old spelling of " + dotted(r.path) + ", still accepted";
    properties[r.old_key] = p;
  }
  return {{"type", {"object", "null"}}, {"additionalProperties", false}, {"properties", properties}};
}

std::string params_help(const FieldTable& table, const std::string& indent) {
  const json defaults = table.defaults();
  std::string text;
  for (const auto& f : table.fields()) {
    text += indent + f.key + ": " + f.doc + "\n";
    if (f.type == FieldType::kStruct) {
      text += params_help(*f.sub, indent + "    ");
      continue;
    }
    text += indent + "    " + field_expectation(f);
    const json& value = defaults.at(f.key);
    const bool unset = value.is_null() || (value.is_string() && value.get<std::string>().empty()) ||
                       (value.is_structured() && value.empty());
    text += unset ? "; not set by default\n" : "; default " + value.dump() + "\n";
    if (f.type == FieldType::kStructMap) text += indent + "    each entry:\n" + params_help(*f.sub, indent + "      ");
  }
  if (!table.renamed().empty()) {
    text += indent + "old spellings, still accepted:\n";
    for (const auto& r : table.renamed()) text += indent + "    " + r.old_key + " = " + dotted(r.path) + "\n";
  }
  return text;
}

}  // namespace olt
