// JSON configuration files: one top-level section per pipeline stage, each read into that
// stage's Options struct (tests/examples/json_config_example_test.cc parses the example):
//
//   { "triplets": { "min_tracks": 30 }, "global_ba": { "huber_factor": 3.0 } }
//
// Every stage's Options is declared JSON-loadable with
// NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT; that is the whole registration needed:
// the accepted keys and their types are taken from the serialised defaults, so a key that
// the struct does not have, or a value of the wrong type, is an InputError naming the file
// and the key rather than a silently ignored typo.
//
// Reading a section only overrides the keys present in the file; other fields keep the
// values already in *options (so presets can be layered).
//
// Unknown top-level sections are caught by a ConfigSchema, the registry of every section a
// command accepts (apps build it from the Options of the stages they run):
//   ConfigSchema schema;
//   schema.Add<TripletOptions>("triplets").Add<GlobalBAOptions>("global_ba");
//   const Config config = LoadConfig(path, schema);
//   ReadSection(config, "triplets", &triplet_options);
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace pgba {

class Config {
 public:
  Config() : root_(nlohmann::json::object()) {}
  // Parses `text`; `origin` names the source in error messages (a file path). Malformed
  // JSON -> InputError "ORIGIN:LINE: malformed JSON at column C: ..."; a top level that is
  // not an object, or a section that is not an object, -> InputError.
  static Config Parse(const std::string& text, const std::string& origin);
  // Reads and parses a file (InputError if missing or unreadable).
  static Config Load(const std::string& path);

  const nlohmann::json& root() const { return root_; }
  const std::string& origin() const { return origin_; }
  bool HasSection(const std::string& section) const { return root_.contains(section); }

 private:
  nlohmann::json root_;
  std::string origin_;
};

namespace internal {
// Checks `given` against `reference` (the serialised defaults) recursively: every key of an
// object must exist in the reference, and every value must have the reference's type
// (any number for a floating-point field, an integral number for an integer field).
// `where` is the dotted key path used in messages.
void CheckAgainstDefaults(const nlohmann::json& given, const nlohmann::json& reference, const std::string& where,
                          const std::string& origin);
// After conversion: every given value must survive Options -> JSON unchanged (catches enum
// names that NLOHMANN_JSON_SERIALIZE_ENUM would silently map to its first value).
void CheckRoundTrip(const nlohmann::json& given, const nlohmann::json& converted, const std::string& where,
                    const std::string& origin);
[[noreturn]] void FailConversion(const std::string& origin, const std::string& section, const std::string& what);
}  // namespace internal

// Overrides the fields of *options present in section `section` (absent section: no-op).
template <typename Options>
void ReadSection(const Config& config, const std::string& section, Options* options) {
  if (!config.HasSection(section)) return;
  nlohmann::json merged = *options;
  internal::CheckAgainstDefaults(config.root().at(section), merged, section, config.origin());
  merged.merge_patch(config.root().at(section));
  Options result;
  try {
    result = merged.template get<Options>();
  } catch (const nlohmann::json::exception& e) {
    internal::FailConversion(config.origin(), section, e.what());
  }
  internal::CheckRoundTrip(config.root().at(section), nlohmann::json(result), section, config.origin());
  *options = result;
}

// The registry of sections a command accepts, each with its Options' keys.
class ConfigSchema {
 public:
  template <typename Options>
  ConfigSchema& Add(const std::string& section, const Options& defaults = Options{}) {
    sections_[section] = defaults;
    return *this;
  }
  // InputError naming the first unknown section or key, or mistyped value.
  void Validate(const Config& config) const;
  bool Knows(const std::string& section) const { return sections_.count(section) > 0; }

 private:
  std::map<std::string, nlohmann::json> sections_;
};

// Config::Load + schema.Validate + CheckOptionRanges (option_ranges.h): the one way a
// command reads its config file.
Config LoadConfig(const std::string& path, const ConfigSchema& schema);

}  // namespace pgba
