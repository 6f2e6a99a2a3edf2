// The example of src/pgba/io/json_config.h, read from the header itself, is a config that
// the pipeline's own schema accepts and that sets what it says (an example with keys the
// schema rejects would teach a config that fails). The header's usage lines are followed here
// verbatim.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "global_ba/global_ba.h"
#include "mapper/pointless_mapper.h"
#include "pgba/io/json_config.h"
#include "pgba/util/error.h"
#include "triplets/triplet_options.h"

namespace pgba {
namespace {

// The first comment line of the header that holds a JSON object: "//   { ... }".
std::string HeaderExample() {
  std::ifstream in(std::string(PGBA_SOURCE_DIR) + "/src/pgba/io/json_config.h");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("//   {", 0) == 0) return line.substr(5);
  return "";
}

TEST(JsonConfigExample, HeaderExampleParsesUnderTheRealSchema) {
  const std::string text = HeaderExample();
  ASSERT_FALSE(text.empty()) << "no example line in json_config.h";
  const Config config = Config::Parse(text, "json_config.h example");

  // The schema of `pgba reconstruct` / `run` (every reconstruction section).
  ConfigSchema full;
  AddPointlessMapperSections(&full);
  EXPECT_NO_THROW(full.Validate(config));

  // The header's own usage lines.
  ConfigSchema schema;
  schema.Add<TripletOptions>("triplets").Add<GlobalBAOptions>("global_ba");
  EXPECT_NO_THROW(schema.Validate(config));
  TripletOptions triplets;
  triplets.min_tracks = 1;
  GlobalBAOptions global_ba;
  global_ba.huber_factor = 0.0;
  ReadSection(config, "triplets", &triplets);
  ReadSection(config, "global_ba", &global_ba);
  EXPECT_EQ(triplets.min_tracks, config.root()["triplets"]["min_tracks"].get<int>());
  EXPECT_EQ(global_ba.huber_factor, config.root()["global_ba"]["huber_factor"].get<double>());
}

// A key in a section that does not hold it (min_points and huber_px are local_hessian's) is
// rejected, naming the key: an example written with them fails the test above.
TEST(JsonConfigExample, KeysOfAnotherSectionAreRejected) {
  ConfigSchema full;
  AddPointlessMapperSections(&full);
  for (const auto& [text, key] : {std::pair<std::string, std::string>{R"({"triplets": {"min_points": 30}})", "min_points"},
                                   {R"({"global_ba": {"huber_px": 1.0}})", "huber_px"}}) {
    try {
      full.Validate(Config::Parse(text, "misplaced"));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pgba
