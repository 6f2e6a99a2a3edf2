// Verification of the registered images (mapper/image_verification.h) on a ring whose truth is
// known: at the true poses every image is verified; an image planted wrong (its pose rotated
// by a few degrees, or its verified pairs alone contradicting it) is caught, registered again
// from the structure close to its true pose, and one that cannot be is dropped with its reason.
#include "mapper/image_verification.h"

#include <gtest/gtest.h>

#include <random>

#include "pgba/geometry/rotation.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

using testing::MakeRingScene;
using testing::RingSceneOptions;

struct Ring {
  Reconstruction rec;
  std::map<uint32_t, Pose> truth;
  std::vector<TwoViewGeometry> pairs;  // neighbours on the ring, two-view rotations from the truth
};

Ring MakeRing(double outliers = 0.0) {
  RingSceneOptions o;
  o.num_images = 16;
  o.num_points = 1500;
  o.outlier_fraction = outliers;
  Ring r;
  r.rec = MakeRingScene(o);
  for (const auto& [id, im] : r.rec.images) r.truth[id] = im.pose;
  std::vector<uint32_t> ids;
  for (const auto& [id, p] : r.truth) ids.push_back(id);
  for (size_t k = 0; k < ids.size(); ++k)
    for (size_t d = 1; d <= 2; ++d) {
      TwoViewGeometry g;
      g.image_id1 = ids[k];
      g.image_id2 = ids[(k + d) % ids.size()];
      g.R_21 = r.truth.at(g.image_id2).R() * r.truth.at(g.image_id1).R().transpose();
      r.pairs.push_back(g);
    }
  return r;
}

const ImageVerdict& VerdictOf(const ImageVerificationResult& v, uint32_t id) {
  for (const ImageVerdict& d : v.verdicts)
    if (d.image_id == id) return d;
  throw std::runtime_error("no verdict");
}

TEST(ImageVerification, EveryImageAtItsTruePoseIsVerified) {
  const Ring r = MakeRing(/*outliers=*/0.03);
  const ImageVerificationResult v = VerifyRegisteredImages(r.rec, r.pairs, r.truth, ImageVerificationOptions{});
  EXPECT_EQ(v.verdicts.size(), r.truth.size());
  EXPECT_EQ(v.num_dropped, 0);
  EXPECT_EQ(v.num_reregistered, 0);
  for (const ImageVerdict& d : v.verdicts) {
    EXPECT_EQ(d.status, ImageVerdictStatus::kVerified) << d.image_id << ": " << d.reason;
    EXPECT_GE(d.evidence.observations_checked, 100);
    EXPECT_GT(d.evidence.inlier_ratio(), 0.9);
    EXPECT_EQ(d.evidence.pairs_checked, 4);
    EXPECT_LT(d.evidence.pair_rotation_deg, 1e-9);
  }
  EXPECT_EQ(v.poses.size(), r.truth.size());
}

// One image rotated by 2 deg (30 px at this focal): its observations do not reproject, the
// pairs disagree by 2 deg (under their 5 deg bound): caught by its observations, and placed
// again from the points of the others at the noise level of one image's pose (0.5 px noise:
// a point-based BA of this ring ends up to 0.13 deg from the truth), a fraction of the planted
// error.
TEST(ImageVerification, AnImageTwoDegreesOffIsRegisteredAgainNearItsTruePose) {
  const Ring r = MakeRing(/*outliers=*/0.03);
  std::map<uint32_t, Pose> poses = r.truth;
  const uint32_t wrong = std::next(poses.begin(), 5)->first;
  std::mt19937_64 rng(1);
  const Pose& t = r.truth.at(wrong);
  poses[wrong] = Pose::FromRC(t.R() * RandomRotationOfAngle(rng, 2.0 * M_PI / 180.0), t.C());
  const ImageVerificationResult v = VerifyRegisteredImages(r.rec, r.pairs, poses, ImageVerificationOptions{});
  const ImageVerdict& d = VerdictOf(v, wrong);
  EXPECT_EQ(d.status, ImageVerdictStatus::kReregistered) << d.reason;
  EXPECT_NE(d.reason.find("reproject"), std::string::npos) << d.reason;
  EXPECT_LT(d.evidence.inlier_ratio(), 0.1);
  EXPECT_NEAR(d.evidence.pair_rotation_deg, 2.0, 0.5);
  EXPECT_LT(RotationAngleDeg(v.poses.at(wrong).R(), t.R()), 0.15);
  EXPECT_NEAR(d.moved_deg, 2.0, 0.15);
  EXPECT_EQ(v.num_reregistered, 1);
  EXPECT_EQ(v.num_dropped, 0);
  for (const ImageVerdict& other : v.verdicts)
    if (other.image_id != wrong) EXPECT_EQ(other.status, ImageVerdictStatus::kVerified) << other.reason;
}

// The pair test alone: an image whose observations cannot be checked (no re-registration
// possible either) and whose verified pairs say it is turned by 30 deg is dropped, the reason
// naming its pairs.
TEST(ImageVerification, AnImageItsPairsContradictIsDroppedWithTheReason) {
  const Ring r = MakeRing();
  std::map<uint32_t, Pose> poses = r.truth;
  const uint32_t wrong = std::next(poses.begin(), 9)->first;
  std::mt19937_64 rng(2);
  poses[wrong] = Pose::FromRC(r.truth.at(wrong).R() * RandomRotationOfAngle(rng, 30.0 * M_PI / 180.0),
                              r.truth.at(wrong).C());
  ImageVerificationOptions o;
  o.min_checked_observations = 100000;  // the observation test and the re-registration out of reach
  const ImageVerificationResult v = VerifyRegisteredImages(r.rec, r.pairs, poses, o);
  const ImageVerdict& d = VerdictOf(v, wrong);
  EXPECT_EQ(d.status, ImageVerdictStatus::kDropped);
  EXPECT_NE(d.reason.find("verified image pairs"), std::string::npos) << d.reason;
  EXPECT_EQ(v.poses.count(wrong), 0u);
  EXPECT_EQ(v.num_dropped, 1);
  const nlohmann::json j = v.ToJson(r.rec);
  ASSERT_EQ(j["images"].size(), 1u);
  EXPECT_EQ(j["images"][0]["image"], r.rec.images.at(wrong).name);
  EXPECT_EQ(j["images"][0]["status"], "dropped");
}

// The record after a model is adjusted again and verified once more: the first round's verdict
// on an image it dropped (absent from the second) or registered again (verified in the second)
// stands, with the counts; the second's own failures stay.
TEST(ImageVerification, KeepFirstVerdictsRecordsWhatHappenedToEachImage) {
  const auto verdict = [](uint32_t id, ImageVerdictStatus status, const std::string& reason) {
    ImageVerdict v;
    v.image_id = id;
    v.status = status;
    v.reason = reason;
    return v;
  };
  ImageVerificationResult first, second;
  first.verdicts = {verdict(1, ImageVerdictStatus::kVerified, ""), verdict(2, ImageVerdictStatus::kReregistered, "moved"),
                    verdict(3, ImageVerdictStatus::kDropped, "bent"), verdict(4, ImageVerdictStatus::kDropped, "first")};
  first.num_reregistered = 1;
  first.num_dropped = 2;
  // Image 3 left out of the second round; image 4 dropped again there with its own reason.
  second.verdicts = {verdict(1, ImageVerdictStatus::kVerified, ""), verdict(2, ImageVerdictStatus::kVerified, ""),
                     verdict(4, ImageVerdictStatus::kDropped, "second")};
  second.num_dropped = 1;
  KeepFirstVerdicts(first, &second);
  ASSERT_EQ(second.verdicts.size(), 4u);
  EXPECT_EQ(second.verdicts[0].status, ImageVerdictStatus::kVerified);
  EXPECT_EQ(second.verdicts[1].status, ImageVerdictStatus::kReregistered);
  EXPECT_EQ(second.verdicts[1].reason, "moved");
  EXPECT_EQ(second.verdicts[2].image_id, 3u);
  EXPECT_EQ(second.verdicts[2].reason, "bent");
  EXPECT_EQ(second.verdicts[3].reason, "second");
  EXPECT_EQ(second.num_reregistered, 1);
  EXPECT_EQ(second.num_dropped, 2);
}

}  // namespace
}  // namespace pgba
