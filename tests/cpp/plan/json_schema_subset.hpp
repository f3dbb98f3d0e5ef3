// Test helper: a validator for the subset of JSON Schema (2020-12) that
// resources/schema/plan.schema.json and cell.schema.json use — type (object, array, string,
// number, integer, boolean), const, enum, required, properties, additionalProperties (boolean),
// items, minItems, maxItems, minimum, maximum, exclusiveMinimum, minLength, maxLength, pattern
// (ECMAScript, unanchored), allOf, anyOf, not, if/then/else, and $ref to "#/$defs/<name>".
// Unknown keywords other than annotations ($schema,
// $id, title, description, $defs) are reported as errors, so the schema cannot silently use more
// than this checks. Returns the list of violations with their JSON pointers (empty = valid).
#pragma once

#include <algorithm>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace curvedslicer::testing {

class SchemaSubsetValidator {
 public:
  explicit SchemaSubsetValidator(nlohmann::json root) : root_(std::move(root)) {}

  std::vector<std::string> validate(const nlohmann::json& doc) const {
    std::vector<std::string> errors;
    check(root_, doc, "", errors);
    return errors;
  }

 private:
  const nlohmann::json& resolve(const nlohmann::json& schema) const {
    if (!schema.contains("$ref")) return schema;
    const std::string ref = schema["$ref"].get<std::string>();
    const std::string prefix = "#/$defs/";
    if (ref.rfind(prefix, 0) != 0) throw std::runtime_error("unsupported $ref " + ref);
    return root_.at("$defs").at(ref.substr(prefix.size()));
  }

  static bool hasType(const nlohmann::json& v, const std::string& type) {
    if (type == "object") return v.is_object();
    if (type == "array") return v.is_array();
    if (type == "string") return v.is_string();
    if (type == "number") return v.is_number();
    if (type == "integer") return v.is_number_integer();
    if (type == "boolean") return v.is_boolean();
    if (type == "null") return v.is_null();
    throw std::runtime_error("unsupported type " + type);
  }

  void check(const nlohmann::json& rawSchema, const nlohmann::json& v, const std::string& at,
             std::vector<std::string>& errors) const {
    const nlohmann::json& schema = resolve(rawSchema);
    for (const auto& item : schema.items()) {
      static const std::vector<std::string> known = {
          "$schema",   "$id",       "title",    "description", "$defs",      "$ref",
          "type",      "const",     "enum",     "required",    "properties", "additionalProperties",
          "items",     "minItems",  "maxItems", "minimum",     "maximum",    "exclusiveMinimum",
          "minLength", "maxLength", "pattern",  "allOf",       "anyOf",      "not",
          "if",        "then",      "else"};
      if (std::find(known.begin(), known.end(), item.key()) == known.end()) {
        throw std::runtime_error("schema keyword outside the supported subset: " + item.key());
      }
    }
    const std::string where = at.empty() ? "/" : at;
    if (schema.contains("type") && !hasType(v, schema["type"].get<std::string>())) {
      errors.push_back(where + ": expected " + schema["type"].get<std::string>());
      return;
    }
    if (schema.contains("const") && v != schema["const"]) {
      errors.push_back(where + ": expected " + schema["const"].dump());
    }
    if (schema.contains("enum")) {
      const auto& options = schema["enum"];
      if (std::find(options.begin(), options.end(), v) == options.end()) {
        errors.push_back(where + ": expected one of " + options.dump());
      }
    }
    if (schema.contains("minimum") && v.is_number() &&
        v.get<double>() < schema["minimum"].get<double>()) {
      errors.push_back(where + ": below the minimum " + schema["minimum"].dump());
    }
    if (schema.contains("maximum") && v.is_number() &&
        v.get<double>() > schema["maximum"].get<double>()) {
      errors.push_back(where + ": above the maximum " + schema["maximum"].dump());
    }
    if (schema.contains("exclusiveMinimum") && v.is_number() &&
        v.get<double>() <= schema["exclusiveMinimum"].get<double>()) {
      errors.push_back(where + ": not above " + schema["exclusiveMinimum"].dump());
    }
    if (v.is_string()) checkString(schema, v.get<std::string>(), where, errors);
    checkCombinations(schema, v, at, errors);
    if (v.is_object()) {
      if (schema.contains("required")) {
        for (const auto& key : schema["required"]) {
          if (!v.contains(key.get<std::string>())) {
            errors.push_back(where + ": lacks " + key.get<std::string>());
          }
        }
      }
      const bool closed =
          schema.contains("additionalProperties") && schema["additionalProperties"] == false;
      for (const auto& item : v.items()) {
        if (schema.contains("properties") && schema["properties"].contains(item.key())) {
          check(schema["properties"][item.key()], item.value(), at + "/" + item.key(), errors);
        } else if (closed) {
          errors.push_back(where + ": unexpected key " + item.key());
        }
      }
    }
    if (v.is_array()) {
      if (schema.contains("minItems") && v.size() < schema["minItems"].get<std::size_t>()) {
        errors.push_back(where + ": fewer than " + schema["minItems"].dump() + " items");
      }
      if (schema.contains("maxItems") && v.size() > schema["maxItems"].get<std::size_t>()) {
        errors.push_back(where + ": more than " + schema["maxItems"].dump() + " items");
      }
      if (schema.contains("items")) {
        for (std::size_t i = 0; i < v.size(); ++i) {
          check(schema["items"], v[i], at + "/" + std::to_string(i), errors);
        }
      }
    }
  }

  bool isValid(const nlohmann::json& schema, const nlohmann::json& v, const std::string& at) const {
    std::vector<std::string> errors;
    check(schema, v, at, errors);
    return errors.empty();
  }

  static void checkString(const nlohmann::json& schema, const std::string& s,
                          const std::string& where, std::vector<std::string>& errors) {
    if (schema.contains("minLength") && s.size() < schema["minLength"].get<std::size_t>()) {
      errors.push_back(where + ": shorter than " + schema["minLength"].dump());
    }
    if (schema.contains("maxLength") && s.size() > schema["maxLength"].get<std::size_t>()) {
      errors.push_back(where + ": longer than " + schema["maxLength"].dump());
    }
    if (schema.contains("pattern") &&
        !std::regex_search(s, std::regex(schema["pattern"].get<std::string>()))) {
      errors.push_back(where + ": does not match " + schema["pattern"].dump());
    }
  }

  void checkCombinations(const nlohmann::json& schema, const nlohmann::json& v,
                         const std::string& at, std::vector<std::string>& errors) const {
    const std::string where = at.empty() ? "/" : at;
    if (schema.contains("allOf")) {
      for (const auto& sub : schema["allOf"]) check(sub, v, at, errors);
    }
    if (schema.contains("anyOf")) {
      const auto& subs = schema["anyOf"];
      if (std::none_of(subs.begin(), subs.end(),
                       [&](const nlohmann::json& sub) { return isValid(sub, v, at); })) {
        errors.push_back(where + ": matches none of anyOf");
      }
    }
    if (schema.contains("not") && isValid(schema["not"], v, at)) {
      errors.push_back(where + ": matches the schema under not");
    }
    if (schema.contains("if")) {
      const char* branch = isValid(schema["if"], v, at) ? "then" : "else";
      if (schema.contains(branch)) check(schema[branch], v, at, errors);
    }
  }

  nlohmann::json root_;
};

}  // namespace curvedslicer::testing
