// Levenberg-Marquardt for the pointless global BA on normal equations assembled motion by
// motion (paper eq. 5 without a robust loss on the motions):
//     min  1/2 sum_s w_s |W_s (x_s(X, sim_s) - x0_s - n_s)|^2.
//
// Why not Ceres here: Ceres forms J^T J from the dense 6N x 6 Jacobian blocks of each motion,
// O(N^3) per motion, which for the whole-track motions (N ~ 10-40 views) costs as much per
// iteration as a point-based BA iteration. Each view's deviation x_k depends only on its own
// pose and the motion's similarity, so J = [A | B] is block-diagonal in the poses and
//     J^T h J:  H_kl = A_k^T h_kl A_l,  H_k,sim = A_k^T (h B)_k,  H_sim = B^T h B,
// O(N^2) per motion with h = W^T W. Each motion's 7 similarity unknowns are then eliminated
// on the spot (7 x 7 Schur complement) and the 6M x 6M pose system, sparse with a block per
// pair of images sharing a motion, is solved by Cholesky (dense up to 1500 unknowns, else
// CHOLMOD supernodal).
// The damping, step acceptance and stopping rules are Ceres' Levenberg-Marquardt ones
// (diag(J^T J) / radius, the same tolerances), so both solvers stop alike.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "modules/global_ba/motion_block_solver_options.h"
#include "modules/global_ba/motion_residual.h"
#include "pgba/optim/pose_parameterization.h"

namespace pgba {

struct MotionBlockTerm {
  const MotionResidual* residual = nullptr;
  const SymmetricMatrix* h = nullptr;  // W^T W of the residual (the local Hessian h_s)
  std::vector<int> poses;  // index into MotionBlockProblem::poses per view
  double* sim = nullptr;   // the motion's 7 similarity parameters
  double weight = 1.0;     // w_s
  // Self-calibration: index into MotionBlockProblem::intrinsics per camera of h, in the order
  // of its intrinsic rows (MotionResidual::intrinsic_sizes).
  std::vector<int> intrinsics;
};

struct MotionBlockProblem {
  std::vector<PoseBlock*> poses;
  // The global intrinsic unknowns (each camera's free parameter values): not eliminated, they
  // border the pose system (a few per camera).
  std::vector<Eigen::VectorXd*> intrinsics;
  std::vector<MotionBlockTerm> terms;
  // Gauge: pose `fixed_pose` held, and centre coordinate `scale_coord` of `scale_pose`.
  int fixed_pose = -1;
  int scale_pose = -1;
  int scale_coord = 0;
};

struct MotionBlockSummary {
  bool usable = true;  // false: the system could not be factorised or the cost is not finite
  std::string message;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double final_radius = 0.0;  // the trust region radius the solve ended with
  // (J^T J)^-1 of the intrinsic unknowns at the end (undamped, similarities eliminated, the
  // gauge held), concatenated in MotionBlockProblem::intrinsics order: times the pixel noise
  // variance, their covariance. Empty without intrinsics or if not factorisable.
  Eigen::MatrixXd intrinsics_inverse_hessian;
};

// Called with (iteration, cost) before the first iteration (0) and after each iteration.
using MotionBlockCallback = std::function<void(int, double)>;

// Total cost 1/2 sum_s w_s |r_s|^2 at the current state.
double MotionBlockCost(const MotionBlockProblem& problem);

MotionBlockSummary SolveMotionBlocks(const MotionBlockProblem& problem, const MotionBlockSolverOptions& options,
                                     const MotionBlockCallback& callback = nullptr);

}  // namespace pgba
