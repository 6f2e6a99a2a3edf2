// Robust rotation averaging (Chatterjee & Govindu, "Efficient and Robust Large-Scale
// Rotation Averaging", ICCV 2013, and "Robust Relative Rotation Averaging", TPAMI 2017).
//
// Unknowns: the world->camera rotation R_i of every image. Observations: relative rotations
// R_ij ~ R_j R_i^T. With right-multiplied increments R_i <- R_i Exp(x_i) (the project's
// convention) the residual of an observation is
//     e_ij = Log(R_j^T R_ij R_i),   and to first order   e_ij(x) = e_ij - (x_j - x_i),
// so every linearised step is a weighted difference system (difference_system.h) solved for
// the three components of x at once. Stages:
//   1. initialisation: chain the observations along a maximum spanning tree. An observation
//      is validated when an independent one (another source: a different pair or triplet)
//      of the same image pair agrees with it, or two independent ones close a triangle with
//      it, within init_consistency_deg. The tree takes validated observations first, best
//      supported (inliers / tracks) first, and unvalidated ones only to connect what the
//      validated ones leave apart: ranked by support alone, a corrupted pair with many
//      inliers would enter the tree and mis-rotate the whole subtree behind it;
//   2. optional L1 stage (Chatterjee's L1RA): a few relinearisations, each solving the
//      linearised L1 problem sum |e_ij(x)| by inner IRLS; it moves the estimate into the
//      basin of the redescending loss even when the tree contains outlier edges;
//   3. IRLS with a robust loss (Geman-McClure, sigma 5 deg by default; l1/2 available):
//      reweight, solve, update, until the largest update is below the step tolerance;
//   4. outlier edges: observations whose residual exceeds inlier_threshold_deg are excluded
//      and IRLS is run again on the rest, from the current estimate. Edges are excluded, not
//      images: an image keeps its rotation as long as inlier observations connect it to the
//      largest inlier component.
// Gauge: the rotation of the image with the largest total support stays fixed.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "averaging/relative_rotations.h"
#include "pgba/optim/loss_function_options.h"
#include "pgba/util/json_fields.h"

namespace pgba {

struct RotationAveragingOptions {
  // Which relative rotations enter and how they are weighted.
  RelativeRotationOptions observations;
  // Start from the spanning-tree chaining; false: start from the rotations passed in (every
  // image of the observations must have one).
  bool spanning_tree_init = true;
  // Agreement (degrees) that validates an observation for the spanning tree (stage 1).
  double init_consistency_deg = 3.0;
  // L1 stage: relinearisations (0 disables), inner IRLS-L1 solves per relinearisation, and
  // its stopping tolerance on the largest update (degrees).
  int max_l1_iterations = 5;
  int l1_inner_iterations = 10;
  double l1_step_tolerance_deg = 1e-3;
  // Robust loss of the IRLS stage and its scale in degrees (config keys "loss",
  // "loss_scale_deg"; the IRLS takes it in radians).
  LossFunctionOptions loss = {LossType::kGemanMcClure, 5.0};
  // IRLS stops after this many iterations or when the largest update is below the
  // tolerance (degrees).
  int max_irls_iterations = 100;
  double step_tolerance_deg = 1e-5;
  // Observations with a residual above this after IRLS are outliers: excluded (stage 4)
  // if exclude_outliers, otherwise only counted in the summary.
  double inlier_threshold_deg = 5.0;
  bool exclude_outliers = true;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
template <class Visit>
void JsonFields(RotationAveragingOptions& o, Visit&& visit) {
  visit("observations", o.observations);
  visit("spanning_tree_init", o.spanning_tree_init);
  visit("init_consistency_deg", o.init_consistency_deg);
  visit("max_l1_iterations", o.max_l1_iterations);
  visit("l1_inner_iterations", o.l1_inner_iterations);
  visit("l1_step_tolerance_deg", o.l1_step_tolerance_deg);
  visit("loss", o.loss.type);
  visit("loss_scale_deg", o.loss.scale);
  visit("max_irls_iterations", o.max_irls_iterations);
  visit("step_tolerance_deg", o.step_tolerance_deg);
  visit("inlier_threshold_deg", o.inlier_threshold_deg);
  visit("exclude_outliers", o.exclude_outliers);
}
PGBA_JSON_FROM_FIELDS(RotationAveragingOptions)

struct RotationAveragingSummary {
  bool success = false;
  std::string message;
  int num_images = 0;
  int num_observations = 0;
  int l1_iterations = 0;
  int irls_iterations = 0;
  double last_step_deg = 0.0;
  bool converged = false;  // IRLS step tolerance reached
  int num_inliers = 0;     // observations with residual below inlier_threshold_deg
  int num_outliers = 0;    // observations above it (excluded if exclude_outliers)
  int tree_validated = 0;  // spanning-tree edges validated by an independent observation
  // Images without a rotation: no inlier observation connects them to the largest inlier
  // component (stage 4).
  std::vector<uint32_t> images_without_inliers;
  double residual_median_deg = 0.0;
  double seconds = 0.0;
};

// Throws InputError for invalid options (non-positive scales or tolerances, negative
// iteration counts).
void ValidateRotationAveragingOptions(const RotationAveragingOptions& options);

// Averages the relative rotations into one rotation per image appearing in them (with
// exclude_outliers: per image of the largest component of the inlier observations; the
// others are listed in summary->images_without_inliers and erased from `rotations`). The
// observation graph must be connected (restrict it to a component first, connectivity.h);
// otherwise, or if a solve fails, returns false with summary->message set and leaves
// `rotations` untouched. With spanning_tree_init = false, `rotations` holds the start.
bool AverageRotations(const std::vector<RelativeRotation>& observations, const RotationAveragingOptions& options,
                      std::map<uint32_t, Eigen::Matrix3d>* rotations, RotationAveragingSummary* summary = nullptr);

// Residual angle (degrees) of one observation under the given rotations.
double RelativeRotationResidualDeg(const RelativeRotation& observation,
                                   const std::map<uint32_t, Eigen::Matrix3d>& rotations);

}  // namespace pgba
