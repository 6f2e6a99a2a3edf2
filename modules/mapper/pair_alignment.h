// Two models of the same tracks in one frame from the verified image pairs between them, for
// models that share too few triangulated points for AlignModels (model_merging.h). A verified
// pair (image a in model A, image b in model B) gives the two-view rotation R_ab and the
// direction of b's centre seen from a; with the poses of a in A and of b in B:
//   - the rotation of the similarity X_A = s R X_B + t: R = R_a^T R_ab^T R_b (each pair one
//     estimate; the largest set of estimates within max_rotation_deg of each other is the
//     consensus, the similarity's R their chordal mean);
//   - scale and translation from the baselines: s R C_b + t = C_a + lambda d (lambda > 0, d
//     the pair's direction in A's frame), three equations per pair and one unknown lambda,
//     so that two pairs with distinct images fix (s, t) and more over-determine them. The
//     linear system is solved in the models' normalised frames; when its smallest singular
//     value relative to its largest is below kMinConditioning the baselines do not fix the
//     scale (all centres and baselines in one plane, as on a flat ring bridged at two
//     gaps: the bridges' directions then fix only two of the three in-plane unknowns).
// The similarity is accepted when at least min_pairs pairs and min_agreeing_ratio of all
// pairs agree on the rotation, every agreeing pair's baseline points forward (lambda > 0)
// and, with more pairs than the similarity needs, lies within max_direction_deg of the
// direction the similarity gives; and when every image of those pairs passes the
// verification of a registered image (image_verification.h) in the merged model.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "mapper/image_verification.h"
#include "mapper/model_merging.h"
#include "pgba/geometry/pose.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct PairAlignmentOptions {
  // Fewest verified pairs between the models that agree (two fix the similarity).
  int min_pairs = 2;
  // Of the pairs between the models, at least this fraction agrees (1: all).
  double min_agreeing_ratio = 0.8;
  // A pair agrees when the rotation it gives is within this of the consensus (degrees).
  double max_rotation_deg = 2.0;
  // With redundant pairs, each baseline within this of the similarity's direction (degrees).
  double max_direction_deg = 5.0;
};

// Smallest relative singular value of the normalised baseline system that fixes the scale.
inline constexpr double kMinConditioning = 0.01;

// `a`, `b`: the poses of the two models (world -> camera, each in its own frame); `pairs`: the
// verified pairs of the view graph (those with one image in each model and none in both are
// used); `tracks` with the mapper's cameras and `verification`: the check of the merged model.
// result.by is kVerifiedPairs; result.reason says why not when !success. Deterministic.
ModelAlignment AlignModelsByPairs(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                  const std::map<uint32_t, Pose>& a, const std::map<uint32_t, Pose>& b,
                                  const PairAlignmentOptions& options, const ImageVerificationOptions& verification);

}  // namespace pgba
