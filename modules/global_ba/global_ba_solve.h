// Inside the global BA module: the solve of the pointless global BA (paper eq. 5) on fixed
// local models, shared by global_ba.cc (PointlessGlobalBA, AveragingGlobalBA) and
// relinearization.cc (RelinearizedGlobalBA), and the per-motion noise quantities both use.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "modules/global_ba/global_ba.h"

namespace pgba::internal {

// IRLS rounds of Levenberg-Marquardt on the models `hessians` (of `motions`) from
// `initial_poses`. `report_start` false: iteration 0 is not reported to the callback (a
// re-linearised solve continues the previous one's curve).
GlobalBAResult RunGlobalBA(const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                           const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                           const GlobalBAIterationCallback& callback, const GcpInput* gcps, bool report_start = true);

// The number of free parameters per camera of h's intrinsic rows (MotionResidual's layout).
std::vector<int> IntrinsicSizes(const LocalHessian& h);

// Degrees of freedom of a motion's local BA residuals: 2 per observation, minus 3 per point
// and the 6N - 7 informative pose directions.
double ResidualDegreesOfFreedom(const LocalHessian& h);

// Per-coordinate pixel noise variance of a motion, from its local BA residuals: the sum of
// squares over ResidualDegreesOfFreedom. NaN when not estimable.
double NoiseVariance(const LocalHessian& h);

}  // namespace pgba::internal
