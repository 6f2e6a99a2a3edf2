// SolverOptions (optim/solver_options.h): every field reaches ceres::Solver::Options, the
// JSON round trip keeps every field, Check() names each field out of range.
#include "pgba/optim/solver_options.h"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "pgba/optim/ceres_solver_options.h"

namespace pgba {
namespace {

// Every field away from its default.
SolverOptions NonDefault() {
  SolverOptions o;
  o.linear_solver_type = ceres::ITERATIVE_SCHUR;
  o.eigen_sparse = true;
  o.max_iterations = 7;
  o.function_tolerance = 1e-3;
  o.gradient_tolerance = 1e-4;
  o.parameter_tolerance = 1e-5;
  o.initial_trust_region_radius = 3e6;
  o.num_threads = 3;
  o.log_progress = true;
  return o;
}

TEST(SolverOptions, CeresOptionsCarryEveryField) {
  const ceres::Solver::Options c = CeresSolverOptions(NonDefault());
  EXPECT_EQ(c.linear_solver_type, ceres::ITERATIVE_SCHUR);
  EXPECT_EQ(c.preconditioner_type, ceres::SCHUR_JACOBI);
  EXPECT_EQ(c.sparse_linear_algebra_library_type, ceres::EIGEN_SPARSE);
  EXPECT_EQ(c.max_num_iterations, 7);
  EXPECT_EQ(c.function_tolerance, 1e-3);
  EXPECT_EQ(c.gradient_tolerance, 1e-4);
  EXPECT_EQ(c.parameter_tolerance, 1e-5);
  EXPECT_EQ(c.initial_trust_region_radius, 3e6);
  EXPECT_EQ(c.num_threads, 3);
  EXPECT_TRUE(c.minimizer_progress_to_stdout);
  EXPECT_EQ(c.logging_type, ceres::PER_MINIMIZER_ITERATION);
  std::string why;
  EXPECT_TRUE(c.IsValid(&why)) << why;
}

TEST(SolverOptions, DefaultsAreCeresOwnButSilent) {
  const ceres::Solver::Options ceres_default;
  const ceres::Solver::Options c = CeresSolverOptions(SolverOptions());
  EXPECT_EQ(c.linear_solver_type, ceres_default.linear_solver_type);
  EXPECT_EQ(c.preconditioner_type, ceres_default.preconditioner_type);
  EXPECT_EQ(c.sparse_linear_algebra_library_type, ceres_default.sparse_linear_algebra_library_type);
  EXPECT_EQ(c.max_num_iterations, ceres_default.max_num_iterations);
  EXPECT_EQ(c.function_tolerance, ceres_default.function_tolerance);
  EXPECT_EQ(c.gradient_tolerance, ceres_default.gradient_tolerance);
  EXPECT_EQ(c.parameter_tolerance, ceres_default.parameter_tolerance);
  EXPECT_EQ(c.initial_trust_region_radius, ceres_default.initial_trust_region_radius);
  EXPECT_EQ(c.num_threads, ceres_default.num_threads);
  EXPECT_FALSE(c.minimizer_progress_to_stdout);
  EXPECT_EQ(c.logging_type, ceres::SILENT);
}

TEST(SolverOptions, ZeroThreadsIsEveryHardwareThread) {
  SolverOptions o;
  o.num_threads = 0;
  EXPECT_EQ(CeresSolverOptions(o).num_threads, std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
}

TEST(SolverOptions, JsonRoundTripKeepsEveryField) {
  const SolverOptions o = NonDefault();
  const nlohmann::json j = o;
  EXPECT_EQ(j.at("linear_solver_type"), "ITERATIVE_SCHUR");
  const SolverOptions back = j.get<SolverOptions>();
  EXPECT_EQ(nlohmann::json(back), j);
  EXPECT_EQ(back.linear_solver_type, o.linear_solver_type);
  EXPECT_EQ(back.initial_trust_region_radius, o.initial_trust_region_radius);
  EXPECT_THROW(nlohmann::json({{"linear_solver_type", "QR_SOMETHING"}}).get<SolverOptions>(),
               nlohmann::json::type_error);
}

TEST(SolverOptions, CheckNamesEachFieldOutOfRange) {
  EXPECT_EQ(SolverOptions().Check(), "");
  EXPECT_EQ(NonDefault().Check(), "");
  const struct {
    void (*spoil)(SolverOptions*);
    const char* message;
  } cases[] = {
      {[](SolverOptions* o) { o->max_iterations = -1; }, "max_iterations = -1 is out of range (>= 0)"},
      {[](SolverOptions* o) { o->function_tolerance = -1e-6; }, "function_tolerance = -9.9999999999999995e-07 is out of range (>= 0)"},
      {[](SolverOptions* o) { o->gradient_tolerance = NAN; }, "gradient_tolerance = nan is out of range (>= 0)"},
      {[](SolverOptions* o) { o->parameter_tolerance = -2; }, "parameter_tolerance = -2 is out of range (>= 0)"},
      {[](SolverOptions* o) { o->initial_trust_region_radius = 0; }, "initial_trust_region_radius = 0 is out of range (> 0)"},
      {[](SolverOptions* o) { o->num_threads = -1; }, "num_threads = -1 is out of range (>= 0)"},
  };
  for (const auto& c : cases) {
    SolverOptions o;
    c.spoil(&o);
    EXPECT_EQ(o.Check(), c.message);
  }
}

}  // namespace
}  // namespace pgba
