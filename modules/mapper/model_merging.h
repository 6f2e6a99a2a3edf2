// Two models of the same tracks in one frame: the similarity that maps model b onto model a,
// from the tracks both have triangulated (TriangulateModel keeps the track ids). Such shared
// points exist when an image is registered into both models (by its triplets in one and its
// absolute pose in the other, or by absolute pose in both): its observations link tracks of
// either side. A 3-point similarity (Umeyama) inside RANSAC; a shared point is an inlier when
// mapped into either model it reprojects into that model's images of its track within the
// threshold, which checks the similarity by the points themselves rather than by a few
// camera centres.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pgba/geometry/sim3.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct ModelAlignmentOptions {
  int min_shared_points = 20;
  int min_inliers = 20;
  double min_inlier_ratio = 0.5;
  double max_reprojection_px = 8.0;
  int ransac_iterations = 300;
  uint64_t seed = 0;
};

// What a merge rests on: the points both models triangulated (AlignModels), or the verified
// image pairs between them (AlignModelsByPairs, pair_alignment.h).
enum class MergeEvidence { kSharedPoints, kVerifiedPairs };

struct ModelAlignment {
  bool success = false;
  MergeEvidence by = MergeEvidence::kSharedPoints;
  Sim3 b_to_a;  // X_a = b_to_a(X_b)
  int shared_points = 0;
  int inliers = 0;
  // kVerifiedPairs: the verified pairs with one image in each model, and how many of them
  // agree with the similarity.
  int pairs = 0;
  int agreeing_pairs = 0;
  // The baselines' smallest relative singular value (pair_alignment.h; 0: not computed).
  double conditioning = 0.0;
  std::vector<std::string> shared_images;  // registered in both models, by name
  std::string reason;                      // why not, when !success

  // "by 25 shared points" / "by 3 verified pairs" (the evidence that agrees).
  std::string Summary() const;
  nlohmann::json ToJson() const;
};

// `a` and `b`: models of the same tracks (points keyed by track id, images with poses and
// their cameras). Deterministic (options.seed).
ModelAlignment AlignModels(const Reconstruction& a, const Reconstruction& b, const ModelAlignmentOptions& options);

}  // namespace pgba
