// One motion's part of the pointless global BA's normal equations (paper eq. 5 with the motion's
// similarity, eq. 4, as unknowns): its residual linearised at the current poses, similarity and
// intrinsics, the blocks it adds to J^T h J and J^T r, and the embedded re-solve of its
// similarity alone. The solver (motion_normal_equations.h) assembles the blocks of every motion.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "modules/global_ba/motion_normal_equations.h"

namespace pgba::internal {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix67 = Eigen::Matrix<double, 6, 7>;
using Matrix7d = Eigen::Matrix<double, 7, 7>;
using Vector7d = Eigen::Matrix<double, 7, 1>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// The current values of the motion's poses and intrinsics (its residual's parameter blocks).
std::vector<const double*> PosePointers(const MotionBlockProblem& p, const MotionBlockTerm& t);
std::vector<const double*> IntrinsicPointers(const MotionBlockProblem& p, const MotionBlockTerm& t);

// One motion's normal equations at the current state (undamped). With K intrinsic rows in h
// (J = identity on them), J^T h J adds H_pk = A^T h_pk, H_sk = B^T h_pk, H_kk = h_kk.
struct TermSystem {
  std::vector<Matrix6d> A;   // d dx_k / d pose_k
  std::vector<Matrix67> B;   // d dx_k / d sim
  std::vector<Matrix6d> Hpp;  // N x N blocks, row-major (k * N + l); the solver sums and releases them
  Eigen::Matrix<double, Eigen::Dynamic, 7> Hps;  // 6N x 7
  Matrix7d Hss;
  Eigen::VectorXd gp;  // 6N
  Vector7d gs;
  Eigen::MatrixXd Hpk;  // 6N x K
  Eigen::Matrix<double, 7, Eigen::Dynamic> Hsk;  // 7 x K
  Eigen::MatrixXd Hkk;  // K x K
  Eigen::VectorXd gk;   // K
};

// The motion's blocks at the current state, `h` its local Hessian (6N + K square).
TermSystem Linearize(const MotionBlockProblem& p, const MotionBlockTerm& t, const Eigen::MatrixXd& h);

// Embedded similarity iterations: each motion's similarity re-solved with the poses held
// (Gauss-Newton on its 7 unknowns, a step kept only if the motion's cost falls). The poses and
// the similarities enter the residual bilinearly (lambda alpha (C - G), eq. 4), and a joint
// Gauss-Newton step crawls along the valley where the scene's scale drifts against the motions'
// scales (measured on the long-focal loops: 25 iterations at rho ~0.63, each gaining 0.05% of
// the cost). With the similarities at their optimum for the new poses, the step is in effect
// one of variable projection (Golub & Pereyra), which does not see that curvature; this is the
// pointless analogue of the embedded point iterations of point-based BA (Jeong et al. 2012).
void OptimizeSimilarity(const MotionBlockProblem& p, const MotionBlockTerm& t, const Eigen::MatrixXd& h,
                        int iterations);

}  // namespace pgba::internal
