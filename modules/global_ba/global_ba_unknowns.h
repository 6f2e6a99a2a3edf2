// Inside the global BA module: the unknowns of one pointless global BA solve (poses,
// per-camera intrinsics, per-motion similarity and IRLS state) and the residual of a motion
// over them, shared by the solve (global_ba.cc) and its two round solvers (global_ba_rounds.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <vector>

#include "modules/global_ba/gcp_terms.h"
#include "modules/global_ba/global_ba.h"
#include "modules/global_ba/motion_residual.h"
#include "modules/global_ba/motion_similarity.h"
#include "modules/global_ba/motion_weight.h"
#include "pgba/optim/pose_parameterization.h"
#include "pgba/util/id_ordered_map.h"

namespace pgba::internal {

// One used motion: its local Hessian, weight matrix, similarity and IRLS state.
struct MotionTerm {
  const LocalHessian* hessian = nullptr;
  MotionWeight W;  // shared with its residuals (motion_weight.h)
  Eigen::VectorXd newton_step;  // LocalHessian::newton_step (kHessian only; empty: zero)
  double unit = 1.0;  // ResidualUnit
  MotionSimilarity sim;
  double irls_weight = 1.0;
};

// A camera's global intrinsic unknowns: its free parameter values (inline storage, so that they
// sit in the contiguous IdOrderedMap like the poses).
struct IntrinsicsBlock {
  std::vector<int> free;
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 8, 1> x;
};

struct Unknowns {
  // Contiguous in id order: Ceres orders the Schur complement's blocks by address (id_ordered_map.h).
  IdOrderedMap<PoseBlock> poses;
  IdOrderedMap<IntrinsicsBlock> intrinsics;  // per camera (self-calibration)
  std::vector<MotionTerm> terms;
  const GcpInput* gcps = nullptr;  // optional
  std::vector<GcpTripletTerm> gcp_terms;
  bool gcp_gauge = false;  // the GCPs fix the gauge
};

std::map<uint32_t, Pose> CurrentPoses(const Unknowns& u);

// Motion t's residual (paper eq. 5) over the current frames of its poses; the caller owns it.
MotionResidual* MakeResidual(const Unknowns& u, const MotionTerm& t);

// The parameter blocks of t's poses and of its cameras' intrinsics, in its residual's order.
std::vector<double*> PoseBlocksOf(Unknowns& u, const MotionTerm& t);
std::vector<double*> IntrinsicBlocksOf(Unknowns& u, const MotionTerm& t);

}  // namespace pgba::internal
