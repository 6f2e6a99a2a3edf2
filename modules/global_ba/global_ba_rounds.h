// Inside the global BA module: one IRLS round of the pointless global BA on fixed weights,
// solved either on the motion-block normal equations (motion_normal_equations.h; no robust loss
// on the motions, no GCPs, gauge by a pose and a scale) or by Ceres (every other case).
#pragma once

#include <Eigen/Core>
#include <string>

#include "modules/global_ba/global_ba.h"
#include "modules/global_ba/global_ba_unknowns.h"

namespace pgba::internal {

// The costs of one round, whichever solver ran it.
struct RoundSummary {
  bool failed = false;
  std::string message;
  double initial_cost = 0.0, final_cost = 0.0;
  int iterations = 0;
  Eigen::MatrixXd intrinsics_inverse_hessian;  // block solver only (MotionBlockSummary)
  double final_radius = 0.0;                   // block solver only
};


// Whether a round can run on the motion-block normal equations (motion_normal_equations.h):
// no robust loss on the motions, no GCP residuals, the gauge held by a pose and a scale.
bool BlockSolverApplies(const GlobalBAOptions& options, double sigma, const Unknowns& u);

// The round on the motion-block normal equations.
RoundSummary SolveRoundByBlocks(const GlobalBAOptions& options, int round, bool report_start, Unknowns* u,
                                GlobalBASummary* summary, const GlobalBAIterationCallback& callback);

// The round by Ceres (Huber on the motions at sigma, GCP residuals, any gauge).
RoundSummary SolveRoundByCeres(const GlobalBAOptions& options, double sigma, int round, bool report_start,
                               Unknowns* u, GlobalBASummary* summary, const GlobalBAIterationCallback& callback);

}  // namespace pgba::internal
