// JSON configs: sections into Options structs, and a clear InputError for every mistake.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "pgba/io/json_config.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

enum class Mode { kFast, kAccurate };
NLOHMANN_JSON_SERIALIZE_ENUM(Mode, {{Mode::kFast, "fast"}, {Mode::kAccurate, "accurate"}})

struct InnerOptions {
  double huber_px = 1.0;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(InnerOptions, huber_px)

struct StageOptions {
  int min_points = 30;
  uint32_t max_views = 4;
  double q = 10.0;
  bool verbose = false;
  std::string name = "default";
  Mode mode = Mode::kFast;
  std::vector<double> weights = {1.0, 2.0};
  InnerOptions inner;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(StageOptions, min_points, max_views, q, verbose, name, mode, weights,
                                                inner)

struct OtherOptions {
  int iterations = 20;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(OtherOptions, iterations)

// The InputError message of `f`, or "" if none was thrown.
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

ConfigSchema Schema() {
  ConfigSchema s;
  s.Add<StageOptions>("triplets").Add<OtherOptions>("global_ba");
  return s;
}

TEST(JsonConfig, ReadsSectionsAndKeepsUnsetFields) {
  const Config c = Config::Parse(
      R"({"triplets": {"min_points": 50, "q": 3, "mode": "accurate", "inner": {"huber_px": 2.5},
          "weights": [0.5]}, "global_ba": {}})",
      "cfg.json");
  Schema().Validate(c);
  StageOptions o;
  o.name = "preset";  // layered: a preset value the file does not touch survives
  ReadSection(c, "triplets", &o);
  EXPECT_EQ(o.min_points, 50);
  EXPECT_EQ(o.q, 3.0);  // an integer literal is fine for a double
  EXPECT_EQ(o.mode, Mode::kAccurate);
  EXPECT_EQ(o.inner.huber_px, 2.5);
  EXPECT_EQ(o.weights, std::vector<double>{0.5});
  EXPECT_EQ(o.name, "preset");
  EXPECT_EQ(o.max_views, 4u);
  OtherOptions other;
  ReadSection(c, "global_ba", &other);
  EXPECT_EQ(other.iterations, 20);
  OtherOptions absent;
  ReadSection(c, "averaging", &absent);  // no such section: defaults
  EXPECT_EQ(absent.iterations, 20);
}

TEST(JsonConfig, MalformedJsonNamesFileLineAndColumn) {
  const std::string msg = ErrorOf([] { Config::Parse("{\n  \"triplets\": {\n    \"q\": 1,,\n  }\n}", "my.json"); });
  EXPECT_EQ(msg.rfind("my.json:3: malformed JSON at column 12", 0), 0u) << msg;
  EXPECT_EQ(ErrorOf([] { Config::Parse("", "e.json"); }).rfind("e.json:1: malformed JSON", 0), 0u);
  EXPECT_NE(ErrorOf([] { Config::Parse("[1, 2]", "a.json"); }).find("a.json: a config must be a JSON object"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { Config::Parse(R"({"triplets": 3})", "s.json"); }).find("section 'triplets' must be"),
            std::string::npos);
}

// nlohmann keeps the last of two equal keys silently and reports 1e999 as a raw
// out_of_range exception without the file: both are InputErrors naming the file.
TEST(JsonConfig, DuplicateKeysAndOverflowingNumbersAreNamed) {
  EXPECT_EQ(ErrorOf([] { Config::Parse(R"({"triplets": {"q": 1, "q": 2}})", "d.json"); }),
            "d.json: duplicate key 'triplets.q'");
  EXPECT_EQ(ErrorOf([] { Config::Parse(R"({"triplets": {}, "triplets": {}})", "d.json"); }),
            "d.json: duplicate key 'triplets'");
  // The same key in sibling objects, or in objects of an array, is not a duplicate.
  EXPECT_EQ(ErrorOf([] { Config::Parse(R"({"a": {"q": 1}, "b": {"q": 1, "l": [{"q": 1}, {"q": 2}]}})", "d.json"); }),
            "");
  const std::string overflow = ErrorOf([] { Config::Parse(R"({"triplets": {"q": 1e999}})", "o.json"); });
  EXPECT_EQ(overflow.rfind("o.json: malformed JSON: number overflow parsing '1e999'", 0), 0u) << overflow;
}

TEST(JsonConfig, UnknownSectionAndKeysAreNamed) {
  const ConfigSchema schema = Schema();
  std::string msg = ErrorOf([&] { schema.Validate(Config::Parse(R"({"tripletz": {}})", "c.json")); });
  EXPECT_NE(msg.find("c.json: unknown section 'tripletz'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("global_ba, triplets"), std::string::npos) << msg;

  const Config typo = Config::Parse(R"({"triplets": {"min_point": 3}})", "c.json");
  EXPECT_NE(ErrorOf([&] { schema.Validate(typo); }).find("unknown key 'triplets.min_point'"), std::string::npos);
  StageOptions o;
  EXPECT_NE(ErrorOf([&] { ReadSection(typo, "triplets", &o); }).find("unknown key 'triplets.min_point'"),
            std::string::npos);
  EXPECT_EQ(o.min_points, 30);  // untouched on error

  const Config nested = Config::Parse(R"({"triplets": {"inner": {"hubr": 1}}})", "c.json");
  EXPECT_NE(ErrorOf([&] { ReadSection(nested, "triplets", &o); }).find("unknown key 'triplets.inner.hubr'"),
            std::string::npos);
}

TEST(JsonConfig, WrongTypesAndValuesAreNamed) {
  StageOptions o;
  auto read = [&](const std::string& body) {
    return ErrorOf([&] { ReadSection(Config::Parse(R"({"triplets": )" + body + "}", "t.json"), "triplets", &o); });
  };
  EXPECT_NE(read(R"({"q": "ten"})").find("'triplets.q': expected a number, found string"), std::string::npos);
  EXPECT_NE(read(R"({"min_points": 1.5})").find("'triplets.min_points': expected an integer"), std::string::npos);
  EXPECT_NE(read(R"({"max_views": -2})").find("'triplets.max_views': expected a non-negative integer"),
            std::string::npos);
  EXPECT_NE(read(R"({"verbose": 1})").find("'triplets.verbose': expected boolean"), std::string::npos);
  EXPECT_NE(read(R"({"q": null})").find("'triplets.q'"), std::string::npos);
  EXPECT_NE(read(R"({"weights": ["a"]})").find("'triplets.weights[0]'"), std::string::npos);
  EXPECT_NE(read(R"({"mode": "fastest"})").find("'triplets.mode': invalid value \"fastest\""), std::string::npos);
  EXPECT_NE(read(R"({"min_points": 3000000000})").find("'triplets.min_points': invalid value"), std::string::npos);
  EXPECT_EQ(read(R"({"min_points": 40.0})"), "");  // integral float is an integer
  EXPECT_EQ(o.min_points, 40);
}

TEST(JsonConfig, LoadFromFile) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_cfg_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path good = dir / "good.json", bad = dir / "bad.json";
  std::ofstream(good) << R"({"global_ba": {"iterations": 7}})";
  std::ofstream(bad) << "{\"global_ba\": {\"iterations\": 7}";
  OtherOptions o;
  ReadSection(LoadConfig(good.string(), Schema()), "global_ba", &o);
  EXPECT_EQ(o.iterations, 7);
  EXPECT_EQ(ErrorOf([&] { Config::Load(bad.string()); }).rfind(bad.string() + ":1: malformed JSON", 0), 0u);
  EXPECT_EQ(ErrorOf([&] { Config::Load((dir / "missing.json").string()); }),
            (dir / "missing.json").string() + ": file not found");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pgba
