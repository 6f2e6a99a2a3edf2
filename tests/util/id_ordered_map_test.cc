// IdOrderedMap: std::map's interface for ids, with elements contiguous and in id order in
// memory (the property Ceres' address-ordered elimination groups need).
#include "pgba/util/id_ordered_map.h"

#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>

namespace pgba {
namespace {

TEST(IdOrderedMap, AddressesFollowIdsWhateverTheInsertionOrder) {
  IdOrderedMap<double> m;
  for (uint32_t id : {7u, 3u, 11u, 5u, 1u}) m[id] = 10.0 * id;
  ASSERT_EQ(m.size(), 5u);
  uint32_t previous = 0;
  const double* previous_address = nullptr;
  for (const auto& [id, value] : m) {
    EXPECT_GT(id, previous);
    EXPECT_EQ(value, 10.0 * id);
    if (previous_address) EXPECT_TRUE(std::less<const double*>()(previous_address, &value));
    previous = id;
    previous_address = &value;
  }
  EXPECT_EQ(m.at(5), 50.0);
  EXPECT_EQ(m.count(4), 0u);
  EXPECT_EQ(m.find(4), m.end());
  EXPECT_THROW(m.at(4), std::out_of_range);
  m[5] = -1.0;  // existing id: no insertion
  EXPECT_EQ(m.size(), 5u);
  EXPECT_EQ(m.at(5), -1.0);
}

}  // namespace
}  // namespace pgba
