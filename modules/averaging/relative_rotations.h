// Relative rotations, the observations of rotation averaging, collected from the verified
// pairs and from the triplets' local poses.
#pragma once

#include <string>

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "pgba/scene/view_graph.h"

namespace pgba {

// R_2 = R_21 R_1 for world->camera rotations R_1, R_2 of images image_id1, image_id2.
struct RelativeRotation {
  uint32_t image_id1 = 0;
  uint32_t image_id2 = 0;
  Eigen::Matrix3d R_21 = Eigen::Matrix3d::Identity();
  // Prior confidence, multiplies the robust IRLS weight.
  double weight = 1.0;
  // Evidence for the maximum-spanning-tree initialisation: inliers of a pair, tracks of a
  // triplet.
  double support = 0.0;
  // Which measurement it comes from (a pair, a triplet; CollectRelativeRotations numbers
  // them); observations sharing a source are not independent evidence for each other (a
  // triplet's three rotations close their cycle whether or not they are right). -1: a
  // source of its own.
  int source = -1;
};

struct RelativeRotationOptions {
  // Use the pairs' essential-matrix rotations.
  bool use_pairs = true;
  // Use the three relative rotations of every triplet (r_b r_a^T from its local poses).
  bool use_triplets = true;
  // IRLS prior weight of a pair's rotation.
  double pair_weight = 1.0;
  // IRLS prior weight of a triplet, shared by its three relative rotations (each gets 2/3 of
  // it: a triplet carries only two independent relative rotations, the third closes the
  // cycle). Triplets come out of a three-view BA and are usually more accurate than pairs.
  double triplet_weight = 1.0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(RelativeRotationOptions, use_pairs, use_triplets, pair_weight,
                                                triplet_weight)

// Relative rotations from the pairs then the triplets (input order; pairs or triplets with
// repeated images are skipped). Sources: pair p is p, triplet t is pairs.size() + t.
std::vector<RelativeRotation> CollectRelativeRotations(const std::vector<TwoViewGeometry>& pairs,
                                                       const std::vector<LocalMotion>& triplets,
                                                       const RelativeRotationOptions& options);

}  // namespace pgba
