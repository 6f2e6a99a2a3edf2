#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "pgba/optim/ceres_solver_options.h"
#include "pgba/optim/solver_options.h"

namespace pgba {
namespace {

std::string OutOfRange(const char* field, double value, const char* range) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", value);
  return std::string(field) + " = " + buf + " is out of range (" + range + ")";
}

}  // namespace

std::string SolverOptions::Check() const {
  if (max_iterations < 0) return OutOfRange("max_iterations", max_iterations, ">= 0");
  if (!(function_tolerance >= 0) || !std::isfinite(function_tolerance))
    return OutOfRange("function_tolerance", function_tolerance, ">= 0");
  if (!(gradient_tolerance >= 0) || !std::isfinite(gradient_tolerance))
    return OutOfRange("gradient_tolerance", gradient_tolerance, ">= 0");
  if (!(parameter_tolerance >= 0) || !std::isfinite(parameter_tolerance))
    return OutOfRange("parameter_tolerance", parameter_tolerance, ">= 0");
  if (!(initial_trust_region_radius > 0) || !std::isfinite(initial_trust_region_radius))
    return OutOfRange("initial_trust_region_radius", initial_trust_region_radius, "> 0");
  if (num_threads < 0) return OutOfRange("num_threads", num_threads, ">= 0");
  return "";
}

ceres::Solver::Options CeresSolverOptions(const SolverOptions& options) {
  ceres::Solver::Options solver;
  solver.linear_solver_type = options.linear_solver_type;
  if (options.linear_solver_type == ceres::ITERATIVE_SCHUR) solver.preconditioner_type = ceres::SCHUR_JACOBI;
  if (options.eigen_sparse) solver.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.gradient_tolerance = options.gradient_tolerance;
  solver.parameter_tolerance = options.parameter_tolerance;
  solver.initial_trust_region_radius = options.initial_trust_region_radius;
  solver.num_threads = options.num_threads > 0 ? options.num_threads
                                               : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  solver.minimizer_progress_to_stdout = options.log_progress;
  solver.logging_type = options.log_progress ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  return solver;
}

void to_json(nlohmann::json& j, const SolverOptions& o) {
  j = {{"linear_solver_type", ceres::LinearSolverTypeToString(o.linear_solver_type)},
       {"eigen_sparse", o.eigen_sparse},
       {"max_iterations", o.max_iterations},
       {"function_tolerance", o.function_tolerance},
       {"gradient_tolerance", o.gradient_tolerance},
       {"parameter_tolerance", o.parameter_tolerance},
       {"initial_trust_region_radius", o.initial_trust_region_radius},
       {"num_threads", o.num_threads},
       {"log_progress", o.log_progress}};
}

void from_json(const nlohmann::json& j, SolverOptions& o) {
  const SolverOptions d;
  const std::string type = j.value("linear_solver_type", std::string(ceres::LinearSolverTypeToString(d.linear_solver_type)));
  if (!ceres::StringToLinearSolverType(type, &o.linear_solver_type))
    throw nlohmann::json::type_error::create(302, "unknown linear_solver_type '" + type + "'", &j);
  o.eigen_sparse = j.value("eigen_sparse", d.eigen_sparse);
  o.max_iterations = j.value("max_iterations", d.max_iterations);
  o.function_tolerance = j.value("function_tolerance", d.function_tolerance);
  o.gradient_tolerance = j.value("gradient_tolerance", d.gradient_tolerance);
  o.parameter_tolerance = j.value("parameter_tolerance", d.parameter_tolerance);
  o.initial_trust_region_radius = j.value("initial_trust_region_radius", d.initial_trust_region_radius);
  o.num_threads = j.value("num_threads", d.num_threads);
  o.log_progress = j.value("log_progress", d.log_progress);
}

}  // namespace pgba
