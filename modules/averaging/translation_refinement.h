// Step 3 of translation averaging (translation_averaging.h): the nonlinear BATA-style
// refinement of the centres over the triplets' baselines and the pairs' directions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "averaging/translation_averaging.h"

namespace pgba {

// One baseline of triplet `triplet`: C_b - C_a ~ S_triplet v (a, b: image nodes).
struct TripletBaseline {
  int triplet = 0;
  int a = 0;
  int b = 0;
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
};

// A pair's unit direction: C_b - C_a ~ |C_b - C_a| u.
struct PairDirection {
  int a = 0;
  int b = 0;
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();
};

// Minimises sum rho(|v - sigma_t (C_b - C_a)|^2) + sum rho(|u - sigma_ab (C_b - C_a)|^2)
// (rho = Huber(options.refine_huber), weighted by triplet_weight / pair_weight) over the
// centres (rows of *centres), sigma_t = 1 / S_t and one sigma per pair, with the centre of
// `fixed_node` and the size of `fixed_triplet` held constant. Updates *centres and *sizes
// (S_t); returns the number of iterations.
int RefineCentres(const std::vector<TripletBaseline>& baselines, const std::vector<PairDirection>& pairs,
                  const TranslationAveragingOptions& options, int fixed_node, int fixed_triplet,
                  Eigen::MatrixXd* centres, std::vector<double>* sizes);

}  // namespace pgba
