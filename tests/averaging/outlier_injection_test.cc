#include "averaging/outlier_injection.h"

#include <gtest/gtest.h>

#include "pgba/geometry/rotation.h"
#include "pgba/util/error.h"
#include "relative_motion_fixture.h"

namespace pgba {
namespace {

// Exactly round(fraction * n) motions are corrupted, the others untouched; a corrupted
// triplet has one view's rotation replaced and every centre kept; same seed, same result.
TEST(OutlierInjection, CorruptsExactlyTheRequestedFraction) {
  const test::GroundTruth gt = test::MakeLayout(test::Layout::kOrbit, 1);
  const test::RelativeMotions clean = test::MakeRelativeMotions(gt, test::NoiseModel(), 2);
  for (OutlierTarget target : {OutlierTarget::kPairs, OutlierTarget::kTriplets, OutlierTarget::kBoth}) {
    test::RelativeMotions m = clean;
    OutlierInjectionOptions options;
    options.fraction = 0.15;
    options.target = target;
    options.seed = 9;
    const OutlierInjectionResult r = InjectRotationOutliers(options, &m.pairs, &m.triplets);
    const size_t want_pairs = target == OutlierTarget::kTriplets ? 0 : std::lround(0.15 * m.pairs.size());
    const size_t want_triplets = target == OutlierTarget::kPairs ? 0 : std::lround(0.15 * m.triplets.size());
    EXPECT_EQ(r.pairs.size(), want_pairs);
    EXPECT_EQ(r.triplets.size(), want_triplets);
    size_t changed_pairs = 0, changed_triplets = 0;
    for (size_t p = 0; p < m.pairs.size(); ++p) {
      const bool changed = RotationAngleDeg(m.pairs[p].R_21, clean.pairs[p].R_21) > 0.0;
      changed_pairs += changed;
      EXPECT_EQ(changed, std::binary_search(r.pairs.begin(), r.pairs.end(), static_cast<int>(p)));
      EXPECT_EQ(m.pairs[p].t_21, clean.pairs[p].t_21);
    }
    for (size_t t = 0; t < m.triplets.size(); ++t) {
      int views_changed = 0;
      for (int k = 0; k < 3; ++k) {
        views_changed += m.triplets[t].local_poses[k].q().coeffs() != clean.triplets[t].local_poses[k].q().coeffs();
        EXPECT_LT((m.triplets[t].local_poses[k].C() - clean.triplets[t].local_poses[k].C()).norm(), 1e-12);
      }
      EXPECT_LE(views_changed, 1);
      changed_triplets += views_changed;
      EXPECT_EQ(views_changed == 1, std::binary_search(r.triplets.begin(), r.triplets.end(), static_cast<int>(t)));
    }
    EXPECT_EQ(changed_pairs, want_pairs);
    EXPECT_EQ(changed_triplets, want_triplets);

    test::RelativeMotions again = clean;
    const OutlierInjectionResult r2 = InjectRotationOutliers(options, &again.pairs, &again.triplets);
    EXPECT_EQ(r.pairs, r2.pairs);
    EXPECT_EQ(r.triplets, r2.triplets);
    for (size_t p = 0; p < m.pairs.size(); ++p) EXPECT_EQ(m.pairs[p].R_21, again.pairs[p].R_21);
  }
}

TEST(OutlierInjection, FractionBounds) {
  std::vector<TwoViewGeometry> pairs(10);
  std::vector<LocalMotion> triplets;
  OutlierInjectionOptions options;
  options.fraction = 1.0;
  EXPECT_EQ(InjectRotationOutliers(options, &pairs, &triplets).pairs.size(), 10u);
  options.fraction = 0.0;
  EXPECT_TRUE(InjectRotationOutliers(options, &pairs, &triplets).pairs.empty());
  options.fraction = 1.5;
  EXPECT_THROW(InjectRotationOutliers(options, &pairs, &triplets), InputError);
  options.fraction = -0.1;
  EXPECT_THROW(InjectRotationOutliers(options, &pairs, &triplets), InputError);
}

}  // namespace
}  // namespace pgba
