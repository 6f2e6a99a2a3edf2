// One description of a Ceres solve for every Ceres call site of the project, embedded in the
// estimator's own options (COLMAP's style: BundleAdjusterOptions::solver,
// GlobalBAOptions::solver, ...) and turned into ceres::Solver::Options by one function, so
// that a tolerance or a thread count means the same thing everywhere and no call site fills
// Ceres' struct by hand.
//
// The defaults are Ceres' own except the logging (silent); each estimator sets the values
// it has always used in its options' default member initialiser (the documented defaults of
// its config keys), so the solves are the same to the last bit.
#pragma once

#include <ceres/types.h>

#include <nlohmann/json.hpp>
#include <string>

namespace pgba {

struct SolverOptions {
  // Ceres' linear solver; ITERATIVE_SCHUR gets the SCHUR_JACOBI preconditioner.
  ceres::LinearSolverType linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  // Eigen's sparse Cholesky instead of Ceres' default library (SuiteSparse): single-threaded,
  // hence deterministic for any thread count.
  bool eigen_sparse = false;
  // Levenberg-Marquardt stopping criteria and first trust region (Ceres' meanings).
  int max_iterations = 50;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  double initial_trust_region_radius = 1e4;
  // Ceres threads, 0 = all hardware threads. 1 keeps results bit-identical from run to run:
  // with more, Ceres sums the cost, gradient and Schur complement over dynamically scheduled
  // chunks, whose order changes the last bits.
  int num_threads = 1;
  // Print Ceres' per-iteration progress to stdout (else silent).
  bool log_progress = false;

  // Empty when valid, else one line naming the field and its valid range.
  std::string Check() const;
};

// CeresSolverOptions(options) (optim/ceres_solver_options.h, apart so that only the files
// calling Ceres include <ceres/solver.h>) fills ceres::Solver::Options from it.

// {"linear_solver_type": "SPARSE_SCHUR", "max_iterations": 50, ...}: every field. The options
// structs that embed a SolverOptions keep their own flat keys (util/json_fields.h).
void to_json(nlohmann::json& j, const SolverOptions& options);
void from_json(const nlohmann::json& j, SolverOptions& options);

}  // namespace pgba
