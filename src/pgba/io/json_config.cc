#include "pgba/io/json_config.h"

#include <cmath>

#include "pgba/io/json_file_reader.h"
#include "pgba/io/option_ranges.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"

namespace pgba {

namespace {

const char* TypeName(const nlohmann::json& j) {
  if (j.is_number_integer()) return "an integer";
  if (j.is_number()) return "a number";
  return j.type_name();
}

}  // namespace

Config Config::Parse(const std::string& text, const std::string& origin) {
  Config c;
  c.origin_ = origin;
  c.root_ = ParseJsonStrictly(text, origin);
  if (!c.root_.is_object()) ThrowInputError(origin, 0, "a config must be a JSON object of sections");
  for (const auto& [name, section] : c.root_.items())
    if (!section.is_object()) ThrowInputError(origin, 0, "section '" + name + "' must be a JSON object");
  return c;
}

Config Config::Load(const std::string& path) { return Parse(ReadRegularFile(path), path); }

namespace internal {

void CheckAgainstDefaults(const nlohmann::json& given, const nlohmann::json& reference, const std::string& where,
                          const std::string& origin) {
  auto fail = [&](const std::string& problem) { ThrowInputError(origin, 0, "'" + where + "': " + problem); };
  if (reference.is_object()) {
    if (!given.is_object()) fail(std::string("expected an object, found ") + TypeName(given));
    for (const auto& [key, value] : given.items()) {
      if (!reference.contains(key)) ThrowInputError(origin, 0, "unknown key '" + where + "." + key + "'");
      CheckAgainstDefaults(value, reference.at(key), where + "." + key, origin);
    }
    return;
  }
  if (reference.is_number_integer()) {
    const bool integral = given.is_number_integer() ||
                          (given.is_number_float() && std::trunc(given.get<double>()) == given.get<double>());
    if (!integral) fail(std::string("expected an integer, found ") + TypeName(given));
    if (reference.is_number_unsigned() && given.get<double>() < 0) fail("expected a non-negative integer");
    return;
  }
  if (reference.is_number()) {
    if (!given.is_number()) fail(std::string("expected a number, found ") + TypeName(given));
    return;
  }
  if (reference.is_array()) {
    if (!given.is_array()) fail(std::string("expected an array, found ") + TypeName(given));
    // Element types are checked against the first default element when there is one.
    if (!reference.empty())
      for (size_t i = 0; i < given.size(); ++i)
        CheckAgainstDefaults(given[i], reference[0], where + "[" + std::to_string(i) + "]", origin);
    return;
  }
  if (reference.is_null()) return;  // no type information
  if (given.type() != reference.type())
    fail(std::string("expected ") + TypeName(reference) + ", found " + TypeName(given));
}

void CheckRoundTrip(const nlohmann::json& given, const nlohmann::json& converted, const std::string& where,
                    const std::string& origin) {
  if (given.is_object() && converted.is_object()) {
    for (const auto& [key, value] : given.items())
      if (converted.contains(key)) CheckRoundTrip(value, converted.at(key), where + "." + key, origin);
    return;
  }
  if (given != converted) ThrowInputError(origin, 0, "'" + where + "': invalid value " + given.dump());
}

void FailConversion(const std::string& origin, const std::string& section, const std::string& what) {
  ThrowInputError(origin, 0, "section '" + section + "': " + what);
}

}  // namespace internal

void ConfigSchema::Validate(const Config& config) const {
  for (const auto& [name, section] : config.root().items()) {
    auto it = sections_.find(name);
    if (it == sections_.end()) {
      std::string known;
      for (const auto& [k, v] : sections_) known += (known.empty() ? "" : ", ") + k;
      ThrowInputError(config.origin(), 0, "unknown section '" + name + "' (known: " + known + ")");
    }
    internal::CheckAgainstDefaults(section, it->second, name, config.origin());
  }
}

Config LoadConfig(const std::string& path, const ConfigSchema& schema) {
  Config c = Config::Load(path);
  schema.Validate(c);
  CheckOptionRanges(c.root(), c.origin());
  return c;
}

}  // namespace pgba
