#include "mapper/linearization_start.h"

#include <algorithm>
#include <cmath>

#include "modules/global_ba/global_ba.h"
#include "modules/local_hessian/local_hessian.h"
#include "pgba/util/upper_median.h"
#include "triplets/triplet_selection.h"

namespace pgba {

double TripletRotationMisfit(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                             const std::vector<LocalMotion>& triplets) {
  std::vector<double> misfit;
  for (const LocalMotion& t : triplets) {
    double worst_px = 0.0;
    bool posed = true;
    for (int a = 0; a < 3 && posed; ++a) {
      const int b = (a + 1) % 3;
      const auto pa = initial.find(t.image_ids[a]);
      const auto pb = initial.find(t.image_ids[b]);
      if (pa == initial.end() || pb == initial.end()) {
        posed = false;
        break;
      }
      const Eigen::Matrix3d global = pa->second.R() * pb->second.R().transpose();
      const Eigen::Matrix3d local = t.local_poses[a].R() * t.local_poses[b].R().transpose();
      const double angle = Eigen::AngleAxisd(global * local.transpose()).angle();
      const double focal = tracks.cameras.at(tracks.images.at(t.image_ids[a]).camera_id).MeanFocal();
      worst_px = std::max(worst_px, angle * focal);
    }
    if (posed) misfit.push_back(worst_px / std::max(t.rms_px, 0.1));
  }
  return misfit.empty() ? 0.0 : UpperMedian(misfit);
}

std::vector<LocalMotion> TripletStartSubset(const std::vector<LocalMotion>& triplets, int max_per_image) {
  if (max_per_image <= 0) return triplets;
  std::vector<TripletCandidate> candidates(triplets.size());
  for (size_t i = 0; i < triplets.size(); ++i) {
    candidates[i].image_ids = TripletImageIds(triplets[i]);
    std::sort(candidates[i].image_ids.begin(), candidates[i].image_ids.end());
    candidates[i].score = static_cast<double>(triplets[i].track_ids.size());
  }
  std::vector<LocalMotion> subset;
  for (const size_t i : SelectTriplets(candidates, max_per_image)) subset.push_back(triplets[i]);
  return subset;
}

std::map<uint32_t, Pose> TripletPointlessStart(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                               const std::vector<LocalMotion>& all_triplets, int max_iterations,
                                               int max_per_image) {
  const std::vector<LocalMotion> triplets = TripletStartSubset(all_triplets, max_per_image);
  // The triplets come converged from their own BA (triplet stage): h is taken where they are.
  LocalHessianOptions paper_lh = PaperTripletLocalHessianOptions();
  paper_lh.solver.max_iterations = 0;
  GlobalBAOptions paper_ba = PaperTripletGlobalBAOptions();
  paper_ba.max_rounds = 1;
  paper_ba.max_relinearizations = 0;
  paper_ba.solver.max_iterations = max_iterations;
  LocalHessianResult h = ComputeLocalHessians(tracks, triplets, paper_lh);
  const GlobalBAResult r =
      RelinearizedGlobalBA(tracks, paper_lh, initial, triplets, std::move(h.hessians), paper_ba);
  std::map<uint32_t, Pose> start = initial;
  for (const auto& [id, pose] : r.poses) start[id] = pose;
  return start;
}

}  // namespace pgba
