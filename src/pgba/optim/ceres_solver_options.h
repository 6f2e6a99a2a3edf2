// SolverOptions (optim/solver_options.h) -> ceres::Solver::Options, in its own header so that
// only the files that call Ceres include <ceres/solver.h>.
#pragma once

#include <ceres/solver.h>

#include "pgba/optim/solver_options.h"

namespace pgba {

// Every field of `options` in Ceres' struct; num_threads 0 -> the hardware threads.
ceres::Solver::Options CeresSolverOptions(const SolverOptions& options);

}  // namespace pgba
