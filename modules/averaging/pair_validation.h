// Validation of the pairs' relative motions by the triplets (before rotation and
// translation averaging).
//
// Why: a pair's essential matrix is not always unique. On a planar scene, every
// correspondence also satisfies the epipolar constraint of the second decomposition of the
// plane's homography (H = R + t n^T / d has two physically valid (R, t, n)), so the 5-point
// RANSAC picks either solution at the whim of the noise; the wrong twin has a rotation off
// by up to the triangulation angle and a translation direction close to the plane normal.
// Narrow fields of view make pair rotations similarly loose (bas-relief ambiguity). Such
// errors of 1-15 degrees are too small for the robust loss of rotation averaging to reject
// (Geman-McClure, 5 degrees) but bias the result. A triplet is estimated by a three-view BA
// whose third view breaks the ambiguity, so a pair whose images belong to a kept triplet is
// checked against it and dropped from both averagings when it disagrees. The twins mostly
// sit on the longer baselines whose triangles fail the rotation-cycle test, i.e. on pairs
// that no triplet covers; those are checked against the rotations averaged from the
// triplets alone (the triplets connect every image that will be registered).
#pragma once

#include <string>

#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "pgba/scene/view_graph.h"

namespace pgba {

struct PairValidationOptions {
  // false keeps every pair.
  bool enabled = true;
  // A pair disagreeing with the triplets containing its two images (median over them) by
  // more than this rotation angle, degrees, or by more than this angle between the
  // translation directions, degrees, is dropped. Noise-level disagreements are a few tenths
  // of a degree in rotation and a few degrees in direction; a planar twin is off by ~1-15
  // degrees in rotation and ~10-90 degrees in direction.
  double max_rotation_deg = 1.0;
  double max_direction_deg = 15.0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(PairValidationOptions, enabled, max_rotation_deg,
                                                max_direction_deg)

// The pairs consistent with the triplets (input order): a pair covered by triplets is
// compared with their relative motions; a pair that no triplet covers is compared, if
// `rotations` is given, with the rotations averaged from the triplets alone (its rotation
// residual), and kept otherwise. `num_rejected` (optional) receives the number dropped.
std::vector<TwoViewGeometry> PairsConsistentWithTriplets(const std::vector<TwoViewGeometry>& pairs,
                                                         const std::vector<LocalMotion>& triplets,
                                                         const PairValidationOptions& options,
                                                         const std::map<uint32_t, Eigen::Matrix3d>* rotations = nullptr,
                                                         int* num_rejected = nullptr);

}  // namespace pgba
