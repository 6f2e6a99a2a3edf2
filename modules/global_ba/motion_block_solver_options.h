// Options of the motion-block solver (motion_normal_equations.h, SolveMotionBlocks): the
// Levenberg-Marquardt settings every solver of the project shares (SolverOptions: max_iterations,
// function_tolerance, parameter_tolerance, initial_trust_region_radius; the Ceres path of the
// global BA reads the same object, with its linear solver and threads), and two settings of
// this solver only. GlobalBAOptions::solver is one, so no field is copied between them.
#pragma once

#include <string>

#include "pgba/optim/solver_options.h"

namespace pgba {

struct MotionBlockSolverOptions : SolverOptions {
  // Gauss-Newton iterations on each motion's similarity after every pose step, the poses held
  // (OptimizeSimilarity in motion_normal_equations.cc: why). 0: the plain joint step.
  int embedded_similarity_iterations = 0;
  // End the solve at the first step refused after one was taken (the state stays at the last
  // accepted one, the radius shrunk), for a solve whose solution is re-linearised next: the
  // models no longer predict the cost there, and new ones do better than a shrinking trust
  // region on the old. Refusals before any step shrink the radius as usual (a radius carried
  // from the previous solve may be too large for the new models). Not a config key: the
  // checked re-linearisation sets it for the solves it re-linearises next.
  bool stop_at_refused_step = false;

  // SolverOptions' ranges and this solver's own.
  std::string Check() const {
    if (embedded_similarity_iterations < 0) return "embedded_similarity_iterations: must be >= 0";
    return SolverOptions::Check();
  }
};

}  // namespace pgba
