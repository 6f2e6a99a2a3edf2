// Independent references for the local Hessian tests (header only): the covariance of a whole
// local BA built densely from Ceres' own Jacobian, a scale-aware matrix comparison, and the
// reprojection cost at given poses with the points re-optimised.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <vector>

#include "modules/local_hessian/local_bundle.h"
#include "pgba/optim/ceres_solver_options.h"
#include "pgba/optim/bundle_adjuster.h"

namespace pgba::testing {

// Covariance of the local BA of `p` over [poses (6N), points (3M)]: Ceres' Jacobian of the
// weighted residuals robustified by the problem's loss (Problem::Evaluate with the loss correction),
// H = J^T J plus `pose_prior` on the pose block, inverted densely. No Schur complement, so
// ReducedCameraMatrix can be checked against the inverse of its camera block.
inline Eigen::MatrixXd DenseCovariance(const LocalBundleProblem& p, const Eigen::MatrixXd& pose_prior) {
  ceres::Problem problem;
  std::vector<double*> blocks;
  std::vector<PoseBlock> poses = p.poses;
  std::vector<Eigen::Vector3d> points = p.points;
  for (auto& b : poses) blocks.push_back(b.x.data());
  for (auto& X : points) blocks.push_back(X.data());
  for (const LocalObservation& o : p.observations)
    problem.AddResidualBlock(
        ReprojectionError::Create(p.cameras[o.view], poses[o.view].R0, o.pixel),
        new ceres::ScaledLoss(p.loss.CreateLossFunction(), p.observation_weight, ceres::TAKE_OWNERSHIP),
        poses[o.view].x.data(), points[o.point].data());
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = blocks;
  eo.apply_loss_function = true;
  ceres::CRSMatrix crs;
  if (!problem.Evaluate(eo, nullptr, nullptr, nullptr, &crs)) return Eigen::MatrixXd();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int i = crs.rows[r]; i < crs.rows[r + 1]; ++i) J(r, crs.cols[i]) = crs.values[i];
  Eigen::MatrixXd H = J.transpose() * J;
  const int n = 6 * p.num_views();
  H.topLeftCorner(n, n) += pose_prior;
  return H.fullPivLu().inverse();
}

// Scale-aware comparison of two 6N x 6N camera matrices (positions scaled by L so that
// rotation and position entries are commensurate): relative Frobenius difference.
inline double RelativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double L) {
  Eigen::VectorXd s(a.rows());
  for (int k = 0; k < a.rows() / 6; ++k) s.segment<6>(6 * k) << L, L, L, 1, 1, 1;
  const Eigen::MatrixXd as = s.asDiagonal() * a * s.asDiagonal();
  const Eigen::MatrixXd bs = s.asDiagonal() * b * s.asDiagonal();
  return (as - bs).norm() / bs.norm();
}

// A reference solve run to the end: tolerances far below what the tests compare (1e-16 on the
// cost and the step, 1e-20 on the gradient), up to 100 iterations, one thread, silent.
inline ceres::Solver::Options ConvergedSolverOptions(ceres::LinearSolverType linear_solver) {
  SolverOptions solver;
  solver.linear_solver_type = linear_solver;
  solver.max_iterations = 100;
  solver.function_tolerance = 1e-16;
  solver.gradient_tolerance = 1e-20;
  solver.parameter_tolerance = 1e-16;
  return CeresSolverOptions(solver);
}

// The local BA cost 1/2 sum w rho(|r|^2) at fixed poses, points re-optimised to convergence
// (the point-based cost as a function of the cameras alone), for a
// triplet: `poses` are its three views.
inline double CostWithPointsOptimised(const LocalBundleProblem& p, const std::vector<Pose>& poses) {
  std::vector<PoseBlock> blocks(3);
  std::vector<Eigen::Vector3d> points = p.points;
  ceres::Problem::Options po;
  ceres::Problem problem(po);
  for (int k = 0; k < 3; ++k) {
    blocks[k] = PoseBlock::FromPose(poses[k]);
    problem.AddParameterBlock(blocks[k].x.data(), 6);
    problem.SetParameterBlockConstant(blocks[k].x.data());
  }
  for (const LocalObservation& o : p.observations)
    problem.AddResidualBlock(
        ReprojectionError::Create(p.cameras[o.view], blocks[o.view].R0, o.pixel),
        new ceres::ScaledLoss(p.loss.CreateLossFunction(), p.observation_weight * o.weight,
                              ceres::TAKE_OWNERSHIP),
        blocks[o.view].x.data(), points[o.point].data());
  ceres::Solver::Summary summary;
  ceres::Solve(ConvergedSolverOptions(ceres::DENSE_SCHUR), &problem, &summary);
  return summary.final_cost;
}

}  // namespace pgba::testing
