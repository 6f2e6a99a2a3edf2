// The rule of the tests on shared data (tests/support/shared_data.h): missing data fails the
// test where PGBA_REQUIRE_SHARED_DATA demands it, and only there.
#include "tests/support/shared_data.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace {

// Sets PGBA_REQUIRE_SHARED_DATA for one scope and restores what the environment held.
class RequireSharedData {
 public:
  explicit RequireSharedData(const char* value) {
    if (const char* v = std::getenv(kName)) saved_ = v;
    if (value) setenv(kName, value, 1);
    else unsetenv(kName);
  }
  ~RequireSharedData() {
    if (saved_) setenv(kName, saved_->c_str(), 1);
    else unsetenv(kName);
  }

 private:
  static constexpr const char* kName = "PGBA_REQUIRE_SHARED_DATA";
  std::optional<std::string> saved_;
};

TEST(SharedData, RequiredOnlyWhenTheVariableSaysSo) {
  {
    RequireSharedData env(nullptr);
    EXPECT_FALSE(pgba::test::SharedDataRequired());
  }
  {
    RequireSharedData env("");
    EXPECT_FALSE(pgba::test::SharedDataRequired());
  }
  {
    RequireSharedData env("0");
    EXPECT_FALSE(pgba::test::SharedDataRequired());
  }
  {
    RequireSharedData env("1");
    EXPECT_TRUE(pgba::test::SharedDataRequired());
  }
}

void NeedMissingData() { PGBA_NEED_SHARED_DATA(false, "no_such_dataset"); }

TEST(SharedData, MissingDataFailsWhereRequired) {
  RequireSharedData env("1");
  EXPECT_FATAL_FAILURE(NeedMissingData(), "shared data missing (PGBA_REQUIRE_SHARED_DATA is set): no_such_dataset");
}

TEST(SharedData, PresentDataGoesOn) {
  RequireSharedData env("1");
  bool reached = false;
  [&] {
    PGBA_NEED_SHARED_DATA(true, "present");
    reached = true;
  }();
  EXPECT_TRUE(reached);
}

}  // namespace
