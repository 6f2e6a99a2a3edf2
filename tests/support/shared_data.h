// Tests on the real photographs of ../shared/datasets (PGBA_SHARED_DIR, set by
// tests/CMakeLists.txt). Where the data must be present (CI: .ci/run exports
// PGBA_REQUIRE_SHARED_DATA=1), a missing dataset fails the test, so that a broken checkout of
// the data cannot turn the real-data tests into silent skips. Elsewhere (a developer without
// the data) the test is skipped and says which dataset it needs.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

namespace pgba::test {

// The folder of shared dataset NAME (it may not exist).
inline std::filesystem::path SharedDataset(const std::string& name) {
  return std::filesystem::path(PGBA_SHARED_DIR) / "datasets" / name;
}

// True when the environment demands the shared data (PGBA_REQUIRE_SHARED_DATA set, not "0").
inline bool SharedDataRequired() {
  const char* v = std::getenv("PGBA_REQUIRE_SHARED_DATA");
  return v != nullptr && *v != '\0' && std::strcmp(v, "0") != 0;
}

}  // namespace pgba::test

// Ends the current test when `present` is false: a failure where the shared data is required,
// a skip otherwise. `what` names the missing data.
#define PGBA_NEED_SHARED_DATA(present, what)                                                            \
  do {                                                                                                  \
    if (!(present)) {                                                                                   \
      if (::pgba::test::SharedDataRequired())                                                           \
        FAIL() << "shared data missing (PGBA_REQUIRE_SHARED_DATA is set): " << what;                    \
      else                                                                                              \
        GTEST_SKIP() << "shared data missing: " << what << " (set PGBA_REQUIRE_SHARED_DATA=1 to fail)"; \
    }                                                                                                   \
  } while (0)
