// Inside the global BA module: the local models of the re-linearised pointless BA
// (RelinearizedGlobalBA, relinearization.cc) and how they are re-taken at a solution.
#pragma once

#include <vector>

#include "modules/global_ba/global_ba.h"
#include "modules/local_hessian/local_hessian.h"
#include "pgba/optim/intrinsics.h"

namespace pgba::internal {

// The models in force: the motions' frames and local Hessians, index-aligned with the motions.
// They start as the caller's vectors, borrowed, and are re-taken into storage of their own, each
// motion's new model replacing its old one as soon as it is made: one model per motion is held,
// not the old and the new set side by side (a motion's h is (6N + K)^2 doubles, together the
// largest memory of a large block). The caller's vectors are never copied as a whole (copying
// all of them each pass cost 15% of the pointless BA's time on a 70-image orbit).
class Models {
 public:
  Models(const std::vector<LocalMotion>& motions, const std::vector<LocalHessian>& hessians)
      : frames_(&motions), hessians_(&hessians) {}
  // The local Hessians handed over: re-taken in place from the first pass on.
  Models(const std::vector<LocalMotion>& motions, std::vector<LocalHessian>&& hessians)
      : frames_(&motions), hessians_(&owned_hessians_), owned_hessians_(std::move(hessians)) {}
  Models(const Models&) = delete;
  Models& operator=(const Models&) = delete;
  const std::vector<LocalMotion>& frames() const { return *frames_; }
  const std::vector<LocalHessian>& hessians() const { return *hessians_; }
  // The local Hessians in force, handed over (copied if still borrowed); frames() stays.
  std::vector<LocalHessian> TakeHessians() {
    if (hessians_ != &owned_hessians_) return *hessians_;
    return std::move(owned_hessians_);
  }

  // The local Hessians of `motions` re-taken where `result` puts them (points re-triangulated,
  // no local iteration): only the motions `result` used and whose Hessian comes out ok replace
  // theirs; the others keep their model. Each track is triangulated from its point in the model
  // of `start` (nullptr: these models), moved into the new frame (TriangulateTrackFrom): the
  // checked cost is then continuous along a step, where a triangulation from scratch dropped
  // points whose consensus search chose another solution. Returns the motions replaced.
  std::vector<int> RetakeAt(const Reconstruction& tracks, const LocalHessianOptions& at_solution,
                            const ObservationShares* shares, const std::vector<LocalMotion>& motions,
                            const GlobalBAResult& result, const Models* start = nullptr);

 private:
  const std::vector<LocalMotion>* frames_;
  const std::vector<LocalHessian>* hessians_;
  std::vector<LocalHessian> owned_hessians_;
  std::vector<LocalMotion> owned_frames_;
};

// The true robust reprojection cost of the motions `used` used, from their models.
double TotalRobustCost(const std::vector<LocalHessian>& models, const GlobalBAResult& used);

// The observation shares of `motions` if at_solution.shared_observation_weighting, else none.
ObservationShares SharesOf(const Reconstruction& tracks, const std::vector<LocalMotion>& motions,
                           const LocalHessianOptions& at_solution);

// The intrinsic unknowns the local Hessians hold, per camera.
FreeIntrinsics FreeIntrinsicsOf(const std::vector<LocalHessian>& hessians);

}  // namespace pgba::internal
