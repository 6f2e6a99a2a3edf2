#include "pgba/io/json_config.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pgba/util/error.h"

namespace pgba {

namespace {

const char* TypeName(const nlohmann::json& j) {
  if (j.is_number_integer()) return "an integer";
  if (j.is_number()) return "a number";
  return j.type_name();
}

// nlohmann reports a byte offset; users want a line and a column.
void LineColumn(const std::string& text, size_t byte, int* line, int* column) {
  *line = 1;
  *column = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++*line;
      *column = 1;
    } else {
      ++*column;
    }
  }
}

}  // namespace

Config Config::Parse(const std::string& text, const std::string& origin) {
  Config c;
  c.origin_ = origin;
  try {
    c.root_ = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is one past the offending character.
    int line, column;
    LineColumn(text, e.byte > 0 ? e.byte - 1 : 0, &line, &column);
    std::string what = e.what();
    const size_t colon = what.find(": ");  // drop "[json.exception.parse_error.101] parse error at ...:"
    if (colon != std::string::npos) what = what.substr(colon + 2);
    ThrowInputError(origin, line, "malformed JSON at column " + std::to_string(column) + ": " + what);
  }
  if (!c.root_.is_object()) ThrowInputError(origin, 0, "a config must be a JSON object of sections");
  for (const auto& [name, section] : c.root_.items())
    if (!section.is_object()) ThrowInputError(origin, 0, "section '" + name + "' must be a JSON object");
  return c;
}

Config Config::Load(const std::string& path) {
  if (!std::filesystem::exists(path)) ThrowInputError(path, 0, "file not found");
  std::ifstream in(path);
  if (!in || std::filesystem::is_directory(path)) ThrowInputError(path, 0, "cannot open file for reading");
  std::stringstream ss;
  ss << in.rdbuf();
  return Parse(ss.str(), path);
}

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
  return c;
}

}  // namespace pgba
