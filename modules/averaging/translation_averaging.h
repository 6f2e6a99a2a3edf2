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

#include "averaging/robust_loss.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct TranslationAveragingOptions {
  // Step 1: robust loss of the log-scale residuals (dimensionless, 0.05 ~ 5%).
  RobustLoss scale_loss = RobustLoss::kHuber;
  double scale_loss_scale = 0.05;
  // Step 2: robust loss of the centre residuals relative to the triplet size.
  RobustLoss centre_loss = RobustLoss::kHuber;
  double centre_loss_scale = 0.02;
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
  double refine_huber = 0.1;
  int max_refine_iterations = 100;
  // Ceres threads; 1 keeps the result bit-identical from run to run.
  int num_threads = 1;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(TranslationAveragingOptions, scale_loss, scale_loss_scale,
                                                centre_loss, centre_loss_scale,
                                                max_irls_iterations, irls_tolerance, refine, use_pair_directions,
                                                pair_weight, triplet_weight, refine_huber, max_refine_iterations,
                                                num_threads)

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
