// Weak pairs confirmed by a third view. At a narrow field of view (an object ring shot with
// a long lens: dino_sparse_ring's 11 degrees) a correct pair's rotation is poorly
// determined by its own matches (rotation and translation nearly trade), so the
// pose-uncertainty check of verification rejects it, while a pair with few, wrong inliers
// can look well conditioned (dino: 16 inliers at a rotation sd of 0.18 deg, 47 deg off).
// Neither count nor conditioning alone separates them; a third view does: a weak pair
// (i, j) is kept when some image k, paired with both, closes the triangle:
//   - rotation cycle: R_ki R_jk R_ij within max_rotation_cycle_deg of the identity;
//   - baselines: the three centre-to-centre directions (each pair's translation, brought
//     into one frame by the pair rotations) lie in one plane, within max_coplanarity_deg;
//   - transfer: at least min_closed_matches features a <-> b of the weak pair whose partners
//     in k agree (a <-> c in (i, k) and b <-> c in (j, k) for the same feature c), i.e. the
//     pair's matches transfer into the third view.
// A wrong pair has no reason to close a triangle with two other pairs on all three counts.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace pgba {

struct TripletConfirmationOptions {
  // Off by default: verification's own checks decide alone.
  bool enabled = false;
  // What makes a pair weak instead of rejected: it failed verification's minimum inlier
  // count or its rotation uncertainty bound, but has at least this many inliers and at
  // most this rotation sd (degrees). 30, not 20: on dino_sparse_ring the pairs with 20-29
  // inliers are the wrong ones (12-13, 13-14: 21 inliers, 9 deg off) and at 20 the weak
  // pairs of temple_sparse_ring's weakly connected images (2 verified pairs) changed its
  // result (median 0.1086 -> 0.1260 deg).
  int min_inliers = 30;
  double max_rotation_sd_deg = 5.0;
  // ... and one of its images has at most this many pairs verified on their own: weak
  // pairs are for weakly connected images. An image with more is placed by its verified
  // pairs, which a weak pair's rotation (1-5 deg off on dino) would only disturb
  // (temple_sparse_ring, every image with 2-4 verified pairs: its one weak pair at 30
  // inliers, 2.0 deg off, moved the median rotation error 0.1086 -> 0.1157 deg).
  int max_verified_pairs = 2;
  // The triangle's tests (see above).
  double max_rotation_cycle_deg = 3.0;
  double max_coplanarity_deg = 5.0;
  int min_closed_matches = 5;
  // An image left with no verified or confirmed pair (the end of a chain whose skip pairs
  // do not match: it is in no triangle) keeps its weak pair with the most inliers to an
  // image that has one: the triplet stage may still attach it by an open triplet, with that
  // stage's own checks (tracks seen by all three views, the triplet BA), and without it the
  // image is lost anyway.
  bool keep_leaf_pairs = true;

  // "" if valid, else "key: problem" (the key relative to the section).
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(TripletConfirmationOptions, enabled, min_inliers,
                                                max_rotation_sd_deg, max_verified_pairs, max_rotation_cycle_deg, max_coplanarity_deg,
                                                min_closed_matches, keep_leaf_pairs)

// One pair's estimate as the confirmation sees it: x_2 = R_21 x_1 + t_21 for the images
// (image1, image2) and its inlier matches (feature of image1, feature of image2).
struct PairEstimate {
  uint32_t image1 = 0, image2 = 0;
  Eigen::Matrix3d R_21 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_21 = Eigen::Vector3d::UnitX();
  std::vector<std::pair<uint32_t, uint32_t>> matches;
  bool weak = false;  // false: verified on its own
};

// Per pair: the third image that confirmed it (the first in image order passing all three
// tests), kLeafPair for a weak pair kept as an image's only link (keep_leaf_pairs), -1 for
// a weak pair neither confirms nor keeps, and -2 for a pair that was not weak.
// A triangle may lean on other weak pairs. Independent of the order of `pairs`.
constexpr int64_t kLeafPair = -3;
std::vector<int64_t> ConfirmWeakPairs(const std::vector<PairEstimate>& pairs,
                                      const TripletConfirmationOptions& options);

// The tests of one triangle (i, j, k) given its three pairs, each oriented as stored
// (either way round): the rotation cycle (degrees), the baselines' largest angle out of
// their common plane (degrees; 90 when two baselines are parallel, a degenerate triangle)
// and the number of closed matches of (i, j).
struct TriangleTest {
  double rotation_cycle_deg = 0.0;
  double coplanarity_deg = 0.0;
  int closed_matches = 0;
};
TriangleTest TestTriangle(uint32_t i, uint32_t j, uint32_t k, const PairEstimate& ij, const PairEstimate& ik,
                          const PairEstimate& jk);

// The triangle's cameras in image i's frame, from its three pairs (either way round):
// rotations from i's frame to camera i, j, k and centres, |C_j - C_i| = 1 (the scale of
// C_k from where the baselines meet). False when two baselines are parallel or the
// baselines do not close (TriangleTest::coplanarity_deg 90).
struct TriangleFrame {
  std::array<Eigen::Matrix3d, 3> R;
  std::array<Eigen::Vector3d, 3> C;
};
bool FrameOfTriangle(uint32_t i, uint32_t j, uint32_t k, const PairEstimate& ij, const PairEstimate& ik,
                     const PairEstimate& jk, TriangleFrame* frame);

// Rotation taking image x's camera frame to the other image's, and the direction of the
// other image's centre in x's frame, for a pair stored either way round.
Eigen::Matrix3d PairRotationFrom(const PairEstimate& p, uint32_t x);
Eigen::Vector3d PairCentreDirectionFrom(const PairEstimate& p, uint32_t x);
// Feature of image x -> its partner in the pair's other image.
std::unordered_map<uint32_t, uint32_t> PairPartnersFrom(const PairEstimate& p, uint32_t x);

}  // namespace pgba
