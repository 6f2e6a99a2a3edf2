// Translation averaging: global camera centres from the triplets' local geometry (and
// optionally the pairs' directions), given the averaged global rotations.
//
// Design choice. Direction-only methods (1DSfM, LUD, BATA on pairwise directions) cannot fix
// the spacing of cameras along a line: on video and aerial strips, where the motion is
// nearly collinear, the pairwise directions are all (nearly) parallel and the positions along
// the strip are unobservable. A triplet, however, carries the ratios of its three baselines
// (its local frame has one consistent scale), and triplets sharing a pair of images carry
// their relative scale. We therefore use the triplets' metric geometry as the primary
// observation and the pairwise directions as a secondary one:
//
// Each triplet t with views a, b gives, once rotated to the global frame by its averaged
// rotation alpha_t (similarity.h), the relative centre
//     C_b - C_a = S_t v_ab,   v_ab = alpha_t^T (c_b - c_a) / L_t,
// with L_t its largest local baseline and S_t its unknown size in the global frame.
//   1. Scales: every triplet sharing the pair (a, b) sees the same baseline length l_ab,
//      hence log l_ab - log S_t = log|v^t_ab|: a robust (IRLS) difference system on the
//      bipartite graph of triplets and image pairs (gauge: the first triplet). Ratios of
//      lengths do not depend on the rotations, so this step is immune to rotation errors.
//   2. Centres: with S_t known, C_b - C_a = S_t v_ab is linear: a robust IRLS difference
//      system on the images, each residual measured relative to its triplet's size S_t
//      (gauge: one centre). Robust loss Huber by default.
//   3. Refinement (Ceres, Huber): the BATA form (Zhuang et al., CVPR 2018, as in GLOMAP's
//      global positioning) generalised to triplets: residuals v_ab - sigma_t (C_b - C_a) with
//      one inverse scale sigma_t per triplet shared by its three baselines, and, if enabled,
//      u_ij - sigma_ij (C_j - C_i) per pair with unit direction u_ij = -R_j^T t_21 and a free
//      inverse scale sigma_ij. Residuals are thereby in units of the baseline (a Huber
//      threshold of 0.1 ~ 6 degrees of direction error), long and short baselines count
//      alike, and the pairs add their direction constraints where triplets are sparse.
//      Gauge: the centre of one image and sigma of the best fitting triplet of step 2 are
//      held constant.
// Finally the solution is centred (centroid 0) and scaled so that the median triplet scale
// lambda_t (global -> local) is 1: global and local units then agree on average.
//
// Preconditions: every triplet has three distinct images with rotations in `rotations`, and
// the triplets are connected through shared image pairs (connectivity.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/optim/loss_function_options.h"
#include "pgba/optim/solver_options.h"
#include "pgba/scene/view_graph.h"
#include "pgba/util/json_fields.h"

namespace pgba {

struct TranslationAveragingOptions {
  // Step 1: robust loss of the log-scale residuals (dimensionless, 0.05 ~ 5%). Config keys
  // "scale_loss" and "scale_loss_scale".
  LossFunctionOptions scale_loss = {LossType::kHuber, 0.05};
  // Step 2: robust loss of the centre residuals relative to the triplet size ("centre_loss",
  // "centre_loss_scale").
  LossFunctionOptions centre_loss = {LossType::kHuber, 0.02};
  // IRLS of steps 1 and 2 stops after this many iterations or when the largest change is
  // below this tolerance (relative to the triplet sizes / in log units). The cap is low on
  // purpose: in the linear regime of the loss IRLS converges slowly, and what still moves
  // after 20 iterations is the scale of outlier triplets, which the robust steps after it
  // down-weight anyway.
  int max_irls_iterations = 20;
  double irls_tolerance = 1e-5;
  // Step 3: nonlinear refinement.
  bool refine = true;
  // Add the pairs' translation directions to the refinement.
  bool use_pair_directions = true;
  double pair_weight = 1.0;
  double triplet_weight = 1.0;
  // Huber loss of the refinement ("refine_huber": 0.1 of the baseline ~ 6 degrees).
  LossFunctionOptions refine_loss = {LossType::kHuber, 0.1};
  // The refinement's solver: sparse Schur on Eigen's (single-threaded) sparse Cholesky, the
  // inverse scales eliminated first; at most 100 iterations ("max_refine_iterations"),
  // function and parameter tolerance 1e-8, 1 Ceres thread ("num_threads"; 1 keeps the result
  // bit-identical from run to run, 0 = all hardware threads).
  SolverOptions refine_solver = [] {
    SolverOptions s;
    s.linear_solver_type = ceres::SPARSE_SCHUR;
    s.eigen_sparse = true;
    s.max_iterations = 100;
    s.function_tolerance = 1e-8;
    s.parameter_tolerance = 1e-8;
    return s;
  }();
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
template <class Visit>
void JsonFields(TranslationAveragingOptions& o, Visit&& visit) {
  visit("scale_loss", o.scale_loss.type);
  visit("scale_loss_scale", o.scale_loss.scale);
  visit("centre_loss", o.centre_loss.type);
  visit("centre_loss_scale", o.centre_loss.scale);
  visit("max_irls_iterations", o.max_irls_iterations);
  visit("irls_tolerance", o.irls_tolerance);
  visit("refine", o.refine);
  visit("use_pair_directions", o.use_pair_directions);
  visit("pair_weight", o.pair_weight);
  visit("triplet_weight", o.triplet_weight);
  visit("refine_huber", o.refine_loss.scale);
  visit("max_refine_iterations", o.refine_solver.max_iterations);
  visit("num_threads", o.refine_solver.num_threads);
}
PGBA_JSON_FROM_FIELDS(TranslationAveragingOptions)

struct TranslationAveragingSummary {
  bool success = false;
  std::string message;
  int num_images = 0;
  int num_triplets = 0;
  int num_pairs = 0;          // pair directions used in the refinement
  int scale_links = 0;        // baselines observed in the scale system
  int scale_iterations = 0;
  int centre_iterations = 0;
  int refine_iterations = 0;
  // Median over the triplets' baselines of |C_b - C_a - S_t v_ab| / S_t at the end.
  double residual_median_rel = 0.0;
  double seconds = 0.0;
  double seconds_scales = 0.0;   // step 1
  double seconds_centres = 0.0;  // step 2
  double seconds_refine = 0.0;   // step 3
};

// Throws InputError for invalid options.
void ValidateTranslationAveragingOptions(const TranslationAveragingOptions& options);

// Centres of all images of the triplets. Returns false (centres untouched, message set) if
// the preconditions fail or a solve is singular.
bool AverageTranslations(const std::vector<LocalMotion>& triplets, const std::vector<TwoViewGeometry>& pairs,
                         const std::map<uint32_t, Eigen::Matrix3d>& rotations,
                         const TranslationAveragingOptions& options, std::map<uint32_t, Eigen::Vector3d>* centres,
                         TranslationAveragingSummary* summary = nullptr);

}  // namespace pgba
