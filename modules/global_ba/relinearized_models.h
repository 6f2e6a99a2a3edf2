// Inside the global BA module: the local models of the re-linearised pointless BA
// (RelinearizedGlobalBA, relinearization.cc) and how they are re-taken at a solution.
#pragma once

#include <vector>

#include "modules/global_ba/global_ba.h"
#include "modules/local_hessian/local_hessian.h"
#include "pgba/optim/intrinsics.h"

namespace pgba::internal {

// The models in force: the motions' frames and local Hessians, index-aligned with the motions.
// They start as the caller's vectors and are replaced by re-linearised ones without copying
// the unchanged (a motion's h is (6N + K)^2 doubles: copying all of them each pass cost 15%
// of the pointless BA's time on a 70-image orbit).
class Models {
 public:
  Models(const std::vector<LocalMotion>& motions, const std::vector<LocalHessian>& hessians)
      : frames_(&motions), hessians_(&hessians) {}
  const std::vector<LocalMotion>& frames() const { return *frames_; }
  const std::vector<LocalHessian>& hessians() const { return *hessians_; }

  // The models re-taken at one solution: index into the motions, frame and local Hessian.
  struct Retaken {
    std::vector<int> index;
    std::vector<LocalMotion> frames;
    std::vector<LocalHessian> hessians;
  };

  // The re-taken models in force from now on; the others kept.
  void Adopt(Retaken&& r);

 private:
  const std::vector<LocalMotion>* frames_;
  const std::vector<LocalHessian>* hessians_;
  std::vector<LocalMotion> owned_frames_;
  std::vector<LocalHessian> owned_hessians_;
};


// The local Hessians of `motions` re-taken where `result` puts them (points re-triangulated,
// no local iteration): only the motions `result` used and whose Hessian came out ok. Each
// track is triangulated from its point in the model in force (`models`), moved into the new
// frame (TriangulateTrackFrom): the checked cost is then continuous along a step, where a
// triangulation from scratch dropped points whose consensus search chose another solution.
Models::Retaken RelinearizeAt(const Reconstruction& tracks, const LocalHessianOptions& at_solution,
                              const ObservationShares* shares, const std::vector<LocalMotion>& motions,
                              const Models& models, const GlobalBAResult& result);

// The true robust reprojection cost of the motions `used` used, from their models (the
// re-taken one where there is one).
double TotalRobustCost(const std::vector<LocalHessian>& models, const Models::Retaken* retaken,
                       const GlobalBAResult& used);

// The observation shares of `motions` if at_solution.shared_observation_weighting, else none.
ObservationShares SharesOf(const Reconstruction& tracks, const std::vector<LocalMotion>& motions,
                           const LocalHessianOptions& at_solution);

// The intrinsic unknowns the local Hessians hold, per camera.
FreeIntrinsics FreeIntrinsicsOf(const std::vector<LocalHessian>& hessians);

}  // namespace pgba::internal
